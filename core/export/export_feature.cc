#include "core/export/export_feature.h"

namespace tinbase {

std::vector<int32_t> OwningFeatures(const Tin& tin, const std::vector<ExportFeature>& features) {
  std::vector<int32_t> owner(tin.triangles.size(), kNoFeature);
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    const TinVertex& a = tin.vertices[tri.v[0]];
    const TinVertex& b = tin.vertices[tri.v[1]];
    const TinVertex& c = tin.vertices[tri.v[2]];
    const Point2 centroid{(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3};
    // Last to first: the first feature found holding the centroid is the one whose paint won.
    for (size_t k = features.size(); k-- > 0;) {
      const ExportFeature& f = features[k];
      if (f.mode != FeatureMode::kFill && f.mode != FeatureMode::kReplace) continue;
      if (!f.inside || f.inside->empty()) continue;
      const Point2 lo = f.inside->min(), hi = f.inside->max();
      if (centroid.x < lo.x || centroid.x > hi.x || centroid.y < lo.y || centroid.y > hi.y)
        continue;
      if (f.inside->Locate(centroid) == PointInPolygon::kOutside) continue;
      owner[t] = static_cast<int32_t>(k);
      break;
    }
  }
  return owner;
}

}  // namespace tinbase
