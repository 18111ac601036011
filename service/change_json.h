// Rows of the change log as the service sends them: the same object in an edit's answer, a
// server-sent event and a long poll's list, so a client handles one shape:
// {"tx", "time", "surface" (name|null), "feature" (id|null), "action", "removed", "added",
//  "bbox": [minx, miny, maxx, maxy] | null, "bbox_lonlat": [w, s, e, n] | null}.
// Thread-safety: one object per thread (it caches surface names and a transformation).
#pragma once

#include <ogr_spatialref.h>

#include <cstdint>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "db/change_log.h"
#include "db/store.h"

namespace tinbase::service {

class ChangeJson {
 public:
  // Describes changes of `store` (whose CRS gives bbox_lonlat; none: bbox_lonlat is null).
  static Result<ChangeJson> For(Store& store);

  // The JSON of `change`; `store` names its surface. Errors: the store's.
  Result<nlohmann::json> Describe(Store& store, const Change& change);
  // [w, s, e, n] of the box's corners and edge midpoints in EPSG:4326, null when they cannot be
  // transformed (the edges of a projected box bend in lon/lat; the midpoints catch most of it).
  nlohmann::json LonLatBox(double min_x, double min_y, double max_x, double max_y) const;

 private:
  struct TransformDeleter {
    void operator()(OGRCoordinateTransformation* t) const;
  };
  std::shared_ptr<OGRCoordinateTransformation> to_lonlat_;
  std::map<int64_t, std::string> surface_names_;
};

}  // namespace tinbase::service
