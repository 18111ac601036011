#include "core/pointcloud/point_cloud.h"

#include <algorithm>

namespace tinbase {

ClassSelection ChooseClasses(const PointCloud& cloud, const std::set<uint8_t>& requested) {
  ClassSelection selection;
  if (!requested.empty()) {
    selection.classes = requested;
    selection.description = "classes";
    for (uint8_t c : requested) {
      // Appended in two steps: GCC 12 warns falsely (-Wrestrict) on " " + std::to_string(c).
      selection.description += ' ';
      selection.description += std::to_string(c);
    }
    return selection;
  }
  const bool has_ground =
      std::any_of(cloud.points.begin(), cloud.points.end(),
                  [](const CloudPoint& p) { return p.classification == kLasClassGround; });
  if (has_ground) {
    selection.classes = {kLasClassGround};
    selection.description = "ground (class 2)";
  } else {
    selection.description = "all points (no point has class 2)";
  }
  return selection;
}

std::vector<CloudPoint> SelectPoints(const PointCloud& cloud, const ClassSelection& selection) {
  if (selection.classes.empty()) return cloud.points;
  std::vector<CloudPoint> out;
  for (const CloudPoint& p : cloud.points) {
    if (selection.Keeps(p.classification)) out.push_back(p);
  }
  return out;
}

}  // namespace tinbase
