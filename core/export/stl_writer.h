// STL writer: a selection of a Tin as binary STL (docs/cli.md, "Export", has the layout).
//
// STL stores float32 coordinates, about 7 significant digits: projected coordinates such as
// UTM's 5 171 234.567 would lose everything below half a metre. So x and y are written relative
// to an origin (x0, y0): the centre of the selection's plan-view box rounded to whole CRS units,
// recorded in the 80-byte header as ASCII,
//   "tinbase STL origin X0 Y0 0 crs LABEL"
// (the CRS label cut to fit; the header never begins with "solid", which readers take for ASCII
// STL). z is written as is (heights are small numbers). Over a selection 10 km across float32
// keeps about a millimetre. Each facet's normal is the unit normal of its float corners
// (counter-clockwise seen from above, so it points up); the attribute byte count is 0. STL has no
// place for tags, visibility or shared vertices: each triangle repeats its corners.
// Thread-safety: pure function.
#pragma once

#include <string>

#include "core/base/status.h"
#include "core/export/mesh_selection.h"
#include "core/geometry/crs.h"
#include "core/tin/tin.h"

namespace tinbase {

struct StlOrigin {
  double x = 0;
  double y = 0;
};

// The origin WriteStl uses for `selection` (whole numbers; (0, 0) when nothing is selected).
StlOrigin StlOriginOf(const Tin& tin, const MeshSelection& selection);

// Writes the selected triangles of `tin` to `path` (created or truncated); `crs` may be null.
// IOError naming `path` when it cannot be opened or written; InvalidArgument when there are
// more triangles than STL's 32-bit count holds.
Status WriteStl(const Tin& tin, const Crs* crs, const MeshSelection& selection,
                const std::string& path);

}  // namespace tinbase
