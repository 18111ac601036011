#include "core/measure/surface_area.h"

#include <algorithm>
#include <map>

namespace tinbase {

namespace {

std::array<Vec3, 3> Corners(const Tin& tin, const TinTriangle& t) {
  std::array<Vec3, 3> c;
  for (int i = 0; i < 3; ++i) {
    const TinVertex& v = tin.vertices[t.v[i]];
    c[i] = {v.x, v.y, v.z};
  }
  return c;
}

}  // namespace

AreaReport MeasureArea(const Tin& tin, const MetricFrame& frame) {
  AreaReport report;
  report.geodesic = frame.geographic();
  std::map<int32_t, AreaSum> by_tag;  // kNoTag sorts first; moved last below
  for (const TinTriangle& t : tin.triangles) {
    if (!t.visible) continue;
    const std::array<Vec3, 3> corners = Corners(tin, t);
    const double plan = frame.PlanArea(corners);
    const double surface = LocalSurfaceArea(frame.Local(corners));
    for (AreaSum* sum : {&report.total, &by_tag[t.tag]}) {
      ++sum->triangles;
      sum->plan += plan;
      sum->surface += surface;
    }
  }
  for (const auto& [tag, sum] : by_tag) {
    const bool known = tag >= 0 && static_cast<size_t>(tag) < tin.tags.size();
    report.tags.push_back(
        {known ? std::optional<std::string>(tin.tags[static_cast<size_t>(tag)]) : std::nullopt,
         sum});
  }
  std::sort(report.tags.begin(), report.tags.end(), [](const TagArea& x, const TagArea& y) {
    if (x.tag.has_value() != y.tag.has_value()) return x.tag.has_value();
    return x.tag < y.tag;
  });
  return report;
}

}  // namespace tinbase
