// Coordinates between the store's CRS and a client's: the `crs=` parameter and lon/lat points a
// client sends, and the lon/lat the answers carry for the viewer (which works in EPSG:4326,
// longitude first). Reprojection goes through core/geometry/reproject.h (OGR/PROJ); heights are
// passed through unchanged (no vertical datum shift). Thread-safety: pure functions (each call
// makes its own transformation, as OGR's are not shared between threads).
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/geometry/predicates.h"
#include "core/tin/tin.h"

namespace tinbase::service {

// EPSG:4326 with longitude first.
Result<Crs> LonLatCrs();

// `points` given in `client` moved into the store's CRS (unchanged when `client` is nullopt).
// InvalidArgument when the store has no CRS to move them into, or naming the first point that
// does not transform.
Result<std::vector<Point2>> PointsToStore(const std::optional<Crs>& store_crs,
                                          const std::optional<Crs>& client,
                                          std::vector<Point2> points);

// `vertices` (x, y in the store's CRS) as lon, lat, z. InvalidArgument naming the first vertex
// that does not transform.
Result<std::vector<TinVertex>> VerticesToLonLat(const Crs& store_crs,
                                                std::vector<TinVertex> vertices);

// The plan box [w, s, e, n] in lon/lat of the store-CRS box (min x, min y, max x, max y), from
// its corners and edge midpoints (a projected box is not a lon/lat box); nullopt without a CRS.
Result<std::optional<std::array<double, 4>>> BoxToLonLat(const std::optional<Crs>& store_crs,
                                                         double min_x, double min_y, double max_x,
                                                         double max_y);

}  // namespace tinbase::service
