// Survey points as WKB: how a `points` feature (db/edit/mass_points.h) keeps its points in
// `features.geometry`.
//
// One OGC MultiPoint Z (ISO WKB, little-endian) in the store's CRS, written through OGR as the
// polygon and line codecs are (core/vector/feature_wkb.h), so any GIS reads the column back. A
// round trip gives the same coordinates to the bit. Thread-safety: pure functions.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/status.h"
#include "core/tin/tin.h"

namespace tinbase {

// The x, y, z of `points` (their kind is not kept).
std::vector<uint8_t> PointsToWkb(const std::vector<TinVertex>& points);
// The points of a (Multi)Point Z, kind kUser. Corruption when `wkb` is not WKB, not a point
// geometry, or has no z.
Result<std::vector<TinVertex>> PointsFromWkb(const std::vector<uint8_t>& wkb);

}  // namespace tinbase
