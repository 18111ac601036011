#include "core/export/export_feature.h"

#include <algorithm>
#include <cmath>

namespace tinbase {

namespace {

// Triangle centroids bucketed on a uniform grid (about four a bucket), so that each feature
// tests only the centroids near its box: a geological map of thousands of polygons over a
// million triangles would otherwise cost triangles x features box tests.
class CentroidGrid {
 public:
  explicit CentroidGrid(std::vector<Point2> points) : points_(std::move(points)) {
    if (points_.empty()) return;
    lo_ = hi_ = points_[0];
    for (const Point2& p : points_) {
      lo_.x = std::min(lo_.x, p.x), lo_.y = std::min(lo_.y, p.y);
      hi_.x = std::max(hi_.x, p.x), hi_.y = std::max(hi_.y, p.y);
    }
    across_ = std::clamp<int64_t>(
        static_cast<int64_t>(std::sqrt(static_cast<double>(points_.size()) / 4.0)), 1, 4096);
    size_x_ = std::max((hi_.x - lo_.x) / static_cast<double>(across_), 1e-300);
    size_y_ = std::max((hi_.y - lo_.y) / static_cast<double>(across_), 1e-300);
    begin_.assign(static_cast<size_t>(across_ * across_ + 1), 0);
    for (const Point2& p : points_) ++begin_[Bucket(p) + 1];
    for (size_t b = 1; b < begin_.size(); ++b) begin_[b] += begin_[b - 1];
    std::vector<uint32_t> next(begin_.begin(), begin_.end() - 1);
    ids_.resize(points_.size());
    for (uint32_t i = 0; i < points_.size(); ++i) ids_[next[Bucket(points_[i])]++] = i;
  }

  const Point2& point(uint32_t id) const { return points_[id]; }

  // Calls fn(id) for every point whose bucket meets [min, max] (a superset of those inside).
  template <typename Fn>
  void ForEachNear(const Point2& min, const Point2& max, Fn&& fn) const {
    if (ids_.empty() || max.x < lo_.x || min.x > hi_.x || max.y < lo_.y || min.y > hi_.y) return;
    const int64_t c0 = Column(min.x), c1 = Column(max.x), r0 = Row(min.y), r1 = Row(max.y);
    for (int64_t r = r0; r <= r1; ++r)
      for (uint32_t k = begin_[r * across_ + c0]; k < begin_[r * across_ + c1 + 1]; ++k)
        fn(ids_[k]);
  }

 private:
  // Clamped as doubles first: a box far outside would overflow the integer.
  int64_t Column(double x) const {
    return static_cast<int64_t>(
        std::clamp((x - lo_.x) / size_x_, 0.0, static_cast<double>(across_ - 1)));
  }
  int64_t Row(double y) const {
    return static_cast<int64_t>(
        std::clamp((y - lo_.y) / size_y_, 0.0, static_cast<double>(across_ - 1)));
  }
  size_t Bucket(const Point2& p) const {
    return static_cast<size_t>(Row(p.y) * across_ + Column(p.x));
  }

  std::vector<Point2> points_;
  Point2 lo_{0, 0}, hi_{0, 0};
  double size_x_ = 1, size_y_ = 1;
  int64_t across_ = 1;
  std::vector<uint32_t> begin_;  // CSR: bucket b holds ids_[begin_[b], begin_[b + 1])
  std::vector<uint32_t> ids_;
};

}  // namespace

std::vector<int32_t> OwningFeatures(const Tin& tin, const std::vector<ExportFeature>& features) {
  std::vector<int32_t> owner(tin.triangles.size(), kNoFeature);
  std::vector<Point2> centroids(tin.triangles.size());
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    const TinVertex& a = tin.vertices[tri.v[0]];
    const TinVertex& b = tin.vertices[tri.v[1]];
    const TinVertex& c = tin.vertices[tri.v[2]];
    centroids[t] = {(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3};
  }
  const CentroidGrid grid(std::move(centroids));
  // Last to first: the first feature found holding a centroid is the one whose paint won, and a
  // triangle once decided is not tested again.
  for (size_t k = features.size(); k-- > 0;) {
    const ExportFeature& f = features[k];
    if (f.mode != FeatureMode::kFill && f.mode != FeatureMode::kReplace) continue;
    if (!f.inside || f.inside->empty()) continue;
    grid.ForEachNear(f.inside->min(), f.inside->max(), [&](uint32_t t) {
      if (owner[t] != kNoFeature) return;
      if (f.inside->Locate(grid.point(t)) == PointInPolygon::kOutside) return;
      owner[t] = static_cast<int32_t>(k);
    });
  }
  return owner;
}

}  // namespace tinbase
