// The JSON of the measures (core/measure/): what `tinbase measure area|volume|slope --json`
// prints and what `GET /surfaces/{s}/measures/...` answers, written in one place so the two
// cannot drift apart. Areas in m2, volumes in m3, angles in degrees. Thread-safety: pure.
#pragma once

#include <nlohmann/json.hpp>

#include "core/measure/slope_aspect.h"
#include "core/measure/surface_area.h"
#include "core/measure/volume.h"
#include "db/query/measure_source.h"

namespace tinbase {

// {"surface", "crs" (label or null), "plan_area": "geodesic"|"map plane", "total": {triangles,
// plan_m2, surface_m2}, "tags": [{triangles, plan_m2, surface_m2, tag}]}.
nlohmann::json AreaJson(const MeasureSource& source, const AreaReport& report);

// {"surface", "level", "inside_polygon", "above_m3", "below_m3", "above_area_m2",
// "below_area_m2", "plan_area_m2"}.
nlohmann::json VolumeJson(const MeasureSource& source, double level, bool inside_polygon,
                          const VolumeReport& volume);

// One triangle's {"triangle" (store id), "slope_deg", "aspect_deg" (null when flat), "tag"}.
// REQUIRES: `slope` is of source.part.tin.
nlohmann::json SlopeJson(const MeasureSource& source, const TriangleSlope& slope);

}  // namespace tinbase
