// SurfaceArea: the plan and 3D area of the visible part of a TIN, in total and per tag.
//
// Plan area is the area of the triangles' plan projection (geodesic on the ellipsoid for a
// geographic CRS, see core/measure/metric_frame.h); 3D area the area of the triangles
// themselves, each measured in its local metric frame. Invisible triangles are not part of the
// surface and are left out. Thread-safety: pure function.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/measure/metric_frame.h"
#include "core/tin/tin.h"

namespace tinbase {

struct AreaSum {
  int64_t triangles = 0;
  double plan = 0;     // m2
  double surface = 0;  // m2, the 3D area
};

struct TagArea {
  std::optional<std::string> tag;  // nullopt: triangles without a tag
  AreaSum area;
};

struct AreaReport {
  AreaSum total;
  std::vector<TagArea> tags;  // by tag value, the untagged last; only tags that occur
  bool geodesic = false;      // plan areas are geodesic (geographic CRS)
};

// The areas of `tin`'s visible triangles.
AreaReport MeasureArea(const Tin& tin, const MetricFrame& frame);

}  // namespace tinbase
