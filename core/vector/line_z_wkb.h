// 3D line geometry as WKB: how a line feature with z from the feature (docs/design.md, "Soft
// lines and z from the feature") keeps its z in `features.geometry`: one ISO MultiLineString Z,
// in the store's CRS, so any GIS reads the z back. Lines draped on the DEM stay 2D
// (core/vector/feature_wkb.h). The encoder has its decoder, and a round trip gives the same
// coordinates to the bit. Thread-safety: pure functions.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/polygon.h"

namespace tinbase {

// REQUIRES: z[k].size() == lines[k].size() for every k.
std::vector<uint8_t> LinesZToWkb(const std::vector<std::vector<Point2>>& lines,
                                 const std::vector<std::vector<double>>& z);
// Corruption when `wkb` is not a (Multi)LineString with z.
Status LinesZFromWkb(const std::vector<uint8_t>& wkb, std::vector<std::vector<Point2>>* lines,
                     std::vector<std::vector<double>>* z);

}  // namespace tinbase
