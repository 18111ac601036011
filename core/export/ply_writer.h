// PLY writer: a selection of a Tin as binary little-endian PLY 1.0 (docs/cli.md, "Export", has
// the layout).
//
//   element vertex N: double x, y, z in the store's CRS (exact, no origin shift);
//   element face M:   list uchar int vertex_indices (0-based, counter-clockwise seen from
//                     above), int tag (-1 = untagged, else the index of a `comment tag` line),
//                     uchar visible (1 or 0).
// The tag values and the CRS live in header comments: `comment tag K VALUE` per tag (line breaks
// in a value become spaces), `comment crs LABEL` and `comment crs_wkt WKT`. Comments rather than
// an extra element because every PLY reader skips comments but not all skip unknown elements.
// Only tags some written face uses are listed, renumbered densely in first-use order.
// Thread-safety: pure function.
#pragma once

#include <string>

#include "core/base/status.h"
#include "core/export/mesh_selection.h"
#include "core/geometry/crs.h"
#include "core/tin/tin.h"

namespace tinbase {

// Writes the selected triangles of `tin` to `path` (created or truncated); `crs` may be null.
// IOError naming `path` when it cannot be opened or written; InvalidArgument when there are more
// vertices than PLY's int indices reach.
Status WritePly(const Tin& tin, const Crs* crs, const MeshSelection& selection,
                const std::string& path);

}  // namespace tinbase
