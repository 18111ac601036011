// Boxes between coordinate systems: a box of one CRS as the smallest box of another that holds
// it, its edges densified so that a curved image of a straight edge (UTM to longitude/latitude,
// say) stays inside. For the lon/lat boxes the viewer places things with (`bbox_lonlat`,
// X-Tinbase-Bbox-Lonlat) and for boxes a client gives with `crs=`. Thread-safety: pure
// functions (each call makes its own transformation).
#pragma once

#include <httplib.h>

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "db/feature_store.h"

namespace tinbase::service {

// The box of `to` holding `box` of `from`. InvalidArgument naming both systems when PROJ has no
// transformation between them or the box does not transform (outside the area of use).
Result<Box> TransformBox(const Box& box, const Crs& from, const Crs& to);

// TransformBox to EPSG:4326 as [west, south, east, north], longitude first.
Result<nlohmann::json> LonLatBox(const Box& box, const Crs& from);

// The `crs` query parameter as a Crs; nullopt when absent. InvalidArgument "parameter 'crs':
// 'x' is not a coordinate system GDAL knows" otherwise.
Result<std::optional<Crs>> CrsParam(const httplib::Request& req);

}  // namespace tinbase::service
