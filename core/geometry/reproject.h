// Reprojection of plan coordinates between two Crs, through GDAL's OGRCoordinateTransformation.
//
// Only x and y change: z is kept as it is (a vertical datum or unit change is not applied, so a
// file in feet reprojected to a metre CRS keeps z in feet). Stateless; thread-safe (each call
// makes its own transformation).
#pragma once

#include <vector>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/tin/tin.h"

namespace tinbase {

// Transforms every vertex's x, y from `from` to `to` in place. Returns InvalidArgument naming
// both systems when GDAL/PROJ has no transformation between them, and naming the first vertex
// that does not transform (outside the area of use, say); on failure `vertices` is unchanged.
Status ReprojectXy(const Crs& from, const Crs& to, std::vector<TinVertex>& vertices);

}  // namespace tinbase
