// What the write routes share (the feature edits of edit_routes.cc and the survey points of
// points_routes.cc): the content type they take, the check that a feature is the path's surface's,
// and the committed change as the answer describes it. So both refuse and answer alike.
#pragma once

#include <httplib.h>

#include <cstdint>
#include <nlohmann/json.hpp>

#include "core/base/status.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase::service {

// Whether the body is declared JSON (application/json or application/geo+json, any parameters);
// answers 415 naming the type sent otherwise.
bool JsonBody(const httplib::Request& req, httplib::Response& res);

// NotFound "no feature 12 in surface 's'" unless feature `id` exists and belongs to `surface`.
Status CheckFeatureOf(Store& store, const SurfaceInfo& surface, int64_t id);

// Change `tx` as the change feed describes it (service/change_json.h: "bbox", "bbox_lonlat",
// ...). Corruption when it is not in the log. REQUIRES: `tx` committed or in the open
// transaction of `store`.
Result<nlohmann::json> DescribeCommittedChange(Store& store, int64_t tx);

}  // namespace tinbase::service
