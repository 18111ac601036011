// Reading a request's parameters: every value from a client is checked here, once, and a bad one
// becomes an InvalidArgument that names the parameter and the text ("parameter 'x': 'abc' is not
// a number"). Routes never parse numbers themselves.
#pragma once

#include <httplib.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/geometry/predicates.h"
#include "db/feature_store.h"
#include "db/query/surface_selection.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase::service {

// The query parameter `name`, or nullopt when absent.
std::optional<std::string> OptionalParam(const httplib::Request& req, const char* name);
// The query parameter `name`; InvalidArgument "missing parameter 'x'" when absent.
Result<std::string> RequiredParam(const httplib::Request& req, const char* name);
// A finite number (no NaN, no infinity, nothing after it).
Result<double> FiniteParam(const httplib::Request& req, const char* name);
// A whole number in [min, max]; `fallback` when absent.
Result<int64_t> IntegerParam(const httplib::Request& req, const char* name, int64_t min,
                             int64_t max, std::optional<int64_t> fallback = std::nullopt);
// "minx,miny,maxx,maxy" of finite numbers with min <= max (ParseBbox); nullopt when absent.
Result<std::optional<Box>> BboxParam(const httplib::Request& req, const char* name = "bbox");
// "true"/"1" or "false"/"0"; `fallback` when absent.
Result<bool> BoolParam(const httplib::Request& req, const char* name, bool fallback);
// A polyline "x1,y1,x2,y2,..." of finite numbers: an even count, at least two points.
Result<std::vector<Point2>> LineParam(const httplib::Request& req, const char* name);
// A coordinate system a client names ("EPSG:4326", WKT, a PROJ string); nullopt when absent.
// Axis order is x = easting/longitude (core/geometry/crs.h).
Result<std::optional<Crs>> CrsParam(const httplib::Request& req, const char* name = "crs");
// The selection of SurfaceFilter from bbox=, feature=, visible_only= and tag=.
Result<SurfaceFilter> FilterParams(const httplib::Request& req);

// The whole number in path capture `index` (req.matches), in [min, max].
Result<int64_t> IntegerPathPart(const httplib::Request& req, size_t index, const char* what,
                                int64_t min, int64_t max);

// The surface named by path capture `index`; NotFound "no surface named 'x'" when absent.
Result<SurfaceInfo> SurfaceFromPath(Store& store, const httplib::Request& req, size_t index = 1);

}  // namespace tinbase::service
