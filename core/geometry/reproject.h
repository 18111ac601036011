// Reprojection of plan coordinates between two Crs, through GDAL's OGRCoordinateTransformation.
//
// ReprojectXy changes x and y only; ConvertHeightUnits rescales z from one system's height unit
// to the other's (US feet to metres, say). No vertical datum shift (ellipsoid to geoid) is
// applied: heights keep their datum. Stateless; thread-safe (each call makes its own
// transformation).
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

// Multiplies every vertex's z by from's metres per height unit over to's
// (Crs::VerticalMetresPerUnit); nothing changes when the units agree.
void ConvertHeightUnits(const Crs& from, const Crs& to, std::vector<TinVertex>& vertices);

}  // namespace tinbase
