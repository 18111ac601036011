// Coordinates between the store's CRS and a client's: the `crs=` parameter and lon/lat points a
// client sends, and the lon/lat the answers carry for the viewer (which works in EPSG:4326,
// longitude first). Reprojection goes through core/geometry/reproject.h (OGR/PROJ); heights are
// passed through unchanged (no vertical datum shift). Thread-safety: pure functions (each call
// makes its own transformation, as OGR's are not shared between threads).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/geometry/predicates.h"
#include "core/tin/tin.h"
#include "db/store.h"

namespace tinbase::service {

// A store's CRS and the transformation of its x, y to lon/lat, made once per request thread and
// kept while the store's WKT stays the same: parsing the WKT and asking PROJ for a
// transformation cost more than the rest of a locate.
class StoreCrs {
 public:
  // This thread's StoreCrs for the CRS `store` has now; nullptr when the store has none. Valid
  // until this thread's next call (one request at a time runs on a thread). Errors: reading the
  // store, an unreadable WKT, or no transformation to lon/lat.
  static Result<const StoreCrs*> Of(Store& store);

  const Crs& crs() const { return crs_; }
  // `vertices` x, y in the store's CRS to lon, lat in place (z unchanged). InvalidArgument naming
  // the first vertex that does not transform (then `vertices` is unchanged).
  Status ToLonLat(std::vector<TinVertex>& vertices) const;

  StoreCrs(std::string wkt, Crs crs, Crs lonlat);
  ~StoreCrs();
  StoreCrs(const StoreCrs&) = delete;
  StoreCrs& operator=(const StoreCrs&) = delete;

 private:
  struct Transform;
  std::string wkt_;
  Crs crs_;
  Crs lonlat_;
  std::unique_ptr<Transform> to_lonlat_;
};

// EPSG:4326 with longitude first.
Result<Crs> LonLatCrs();

// `points` given in `client` moved into the store's CRS (unchanged when `client` is nullopt).
// InvalidArgument when the store has no CRS to move them into, or naming the first point that
// does not transform.
Result<std::vector<Point2>> PointsToStore(const StoreCrs* store_crs,
                                          const std::optional<Crs>& client,
                                          std::vector<Point2> points);

// The plan box [w, s, e, n] in lon/lat of the store-CRS box (min x, min y, max x, max y), from
// its corners and edge midpoints (a projected box is not a lon/lat box); nullopt without a CRS.
Result<std::optional<std::array<double, 4>>> BoxToLonLat(const std::optional<Crs>& store_crs,
                                                         double min_x, double min_y, double max_x,
                                                         double max_y);

}  // namespace tinbase::service
