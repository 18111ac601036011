// OBJ writer: a selection of a Tin as Wavefront OBJ text.
//
// `v x y z` per vertex in the store's CRS, each number the shortest text that reads back as
// exactly the same double; `f a b c` per triangle, 1-based, counter-clockwise seen from above.
// Comments at the top name the CRS (label and one-line WKT) and the counts. OBJ has no place
// for tags or visibility. Thread-safety: pure function.
#pragma once

#include <string>

#include "core/base/status.h"
#include "core/export/mesh_selection.h"
#include "core/geometry/crs.h"
#include "core/tin/tin.h"

namespace tinbase {

// Writes the selected triangles of `tin` to `path` (created or truncated). `crs` may be null.
// IOError naming `path` when it cannot be opened or written.
Status WriteObj(const Tin& tin, const Crs* crs, const MeshSelection& selection,
                const std::string& path);

}  // namespace tinbase
