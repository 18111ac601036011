// Feature geometry as WKB: how a feature's polygons or lines are kept in `features.geometry`.
//
// Polygons are written as one OGC MultiPolygon, lines as one MultiLineString, in the store's CRS,
// through OGR so any GIS reads the column back. Each encoder has its decoder, and a round trip
// gives the same coordinates to the bit. Thread-safety: pure functions.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/polygon.h"

namespace tinbase {

std::vector<uint8_t> PolygonsToWkb(const std::vector<Polygon>& polygons);
// Corruption when `wkb` is not a (Multi)Polygon, or has a polygon without rings, a ring of fewer
// than 3 vertices or a vertex that is not finite.
Result<std::vector<Polygon>> PolygonsFromWkb(const std::vector<uint8_t>& wkb);

std::vector<uint8_t> LinesToWkb(const std::vector<std::vector<Point2>>& lines);
// Corruption when `wkb` is not a (Multi)LineString.
Result<std::vector<std::vector<Point2>>> LinesFromWkb(const std::vector<uint8_t>& wkb);

}  // namespace tinbase
