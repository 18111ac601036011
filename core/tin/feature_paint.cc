#include "core/tin/feature_paint.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "core/geometry/polygon_locator.h"

namespace tinbase {

namespace {

Point2 Centroid(const Tin& tin, const TinTriangle& t) {
  const TinVertex& a = tin.vertices[t.v[0]];
  const TinVertex& b = tin.vertices[t.v[1]];
  const TinVertex& c = tin.vertices[t.v[2]];
  return {(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3};
}

// Points bucketed on a uniform grid (about four a bucket), so that a feature visits only the
// centroids near its box instead of every triangle of the surface once per feature: a whole map
// painted at once would otherwise cost triangles x features.
class PointBuckets {
 public:
  explicit PointBuckets(const std::vector<Point2>& points) {
    if (points.empty()) return;
    min_x_ = max_x_ = points[0].x, min_y_ = max_y_ = points[0].y;
    for (const Point2& p : points) {
      min_x_ = std::min(min_x_, p.x), max_x_ = std::max(max_x_, p.x);
      min_y_ = std::min(min_y_, p.y), max_y_ = std::max(max_y_, p.y);
    }
    const double side = std::sqrt(static_cast<double>(points.size()) / 4.0);
    across_ = std::clamp<int64_t>(static_cast<int64_t>(side), 1, 4096);
    size_x_ = std::max((max_x_ - min_x_) / static_cast<double>(across_), 1e-300);
    size_y_ = std::max((max_y_ - min_y_) / static_cast<double>(across_), 1e-300);
    begin_.assign(static_cast<size_t>(across_ * across_ + 1), 0);
    for (const Point2& p : points) ++begin_[Bucket(p) + 1];
    for (size_t b = 1; b < begin_.size(); ++b) begin_[b] += begin_[b - 1];
    std::vector<uint32_t> next(begin_.begin(), begin_.end() - 1);
    ids_.resize(points.size());
    for (uint32_t i = 0; i < points.size(); ++i) ids_[next[Bucket(points[i])]++] = i;
  }

  // Calls fn(id) for every point whose bucket meets [min, max] (a superset of those inside).
  template <typename Fn>
  void ForEachNear(const Point2& min, const Point2& max, Fn&& fn) const {
    if (ids_.empty() || max.x < min_x_ || min.x > max_x_ || max.y < min_y_ || min.y > max_y_)
      return;
    const int64_t c0 = Column(min.x), c1 = Column(max.x), r0 = Row(min.y), r1 = Row(max.y);
    for (int64_t r = r0; r <= r1; ++r)
      for (uint32_t k = begin_[r * across_ + c0]; k < begin_[r * across_ + c1 + 1]; ++k)
        fn(ids_[k]);
  }

 private:
  // Clamped as doubles first: a box far outside would overflow the integer.
  int64_t Column(double x) const {
    return static_cast<int64_t>(
        std::clamp((x - min_x_) / size_x_, 0.0, static_cast<double>(across_ - 1)));
  }
  int64_t Row(double y) const {
    return static_cast<int64_t>(
        std::clamp((y - min_y_) / size_y_, 0.0, static_cast<double>(across_ - 1)));
  }
  size_t Bucket(const Point2& p) const {
    return static_cast<size_t>(Row(p.y) * across_ + Column(p.x));
  }

  double min_x_ = 0, min_y_ = 0, max_x_ = 0, max_y_ = 0, size_x_ = 1, size_y_ = 1;
  int64_t across_ = 1;
  std::vector<uint32_t> begin_;  // CSR: bucket b holds ids_[begin_[b], begin_[b + 1])
  std::vector<uint32_t> ids_;
};

}  // namespace

Paint ComputePaint(const Tin& tin, const std::vector<PaintedFeature>& features) {
  const size_t n = tin.triangles.size();
  Paint paint;
  paint.visible.assign(n, 1);
  paint.tag.assign(n, kNoTag);
  std::vector<Point2> centroids(n);
  for (size_t t = 0; t < n; ++t) centroids[t] = Centroid(tin, tin.triangles[t]);

  // Clip polygons act as one union; with none, clipping hides nothing.
  std::vector<uint8_t> in_clip;
  std::vector<uint8_t> replaced(tin.vertices.size(), 0);
  std::vector<double> level(tin.vertices.size(), 0);
  const PointBuckets buckets(centroids);
  for (const PaintedFeature& feature : features) {
    assert(feature.tag == kNoTag ||
           (feature.tag >= 0 && static_cast<size_t>(feature.tag) < tin.tags.size()));
    if (feature.mode == FeatureMode::kClip && in_clip.empty()) in_clip.assign(n, 0);
    if (!feature.inside || feature.inside->empty()) continue;
    const PolygonLocator& locator = *feature.inside;
    if (feature.mode == FeatureMode::kReplace) {
      // A vertex on the ring is part of the flat replaced area, so boundary counts.
      for (uint32_t v = 0; v < tin.vertices.size(); ++v) {
        const TinVertex& p = tin.vertices[v];
        if (locator.Locate({p.x, p.y}) == PointInPolygon::kOutside) continue;
        replaced[v] = 1;
        level[v] = feature.level;
      }
    }
    if (feature.mode != FeatureMode::kClip && feature.mode != FeatureMode::kErase) continue;
    buckets.ForEachNear(locator.min(), locator.max(), [&](uint32_t t) {
      if (locator.Locate(centroids[t]) == PointInPolygon::kOutside) return;
      if (feature.mode == FeatureMode::kClip)
        in_clip[t] = 1;
      else
        paint.visible[t] = 0;
    });
  }
  // Tags: the last fill or replace feature holding a centroid wins, so they are tested last to
  // first and a triangle is decided by the first that holds it (in a map of neighbouring
  // polygons whose boxes overlap, most of the others are then never tested).
  std::vector<uint8_t> decided(n, 0);
  for (auto it = features.rbegin(); it != features.rend(); ++it) {
    const PaintedFeature& feature = *it;
    if (feature.mode != FeatureMode::kFill && feature.mode != FeatureMode::kReplace) continue;
    if (!feature.inside || feature.inside->empty()) continue;
    const PolygonLocator& locator = *feature.inside;
    buckets.ForEachNear(locator.min(), locator.max(), [&](uint32_t t) {
      if (decided[t] || locator.Locate(centroids[t]) == PointInPolygon::kOutside) return;
      decided[t] = 1;
      paint.tag[t] = feature.tag;
    });
  }
  if (!in_clip.empty()) {
    for (size_t t = 0; t < n; ++t)
      if (!in_clip[t]) paint.visible[t] = 0;
  }
  for (uint32_t v = 0; v < tin.vertices.size(); ++v)
    if (replaced[v]) paint.levels.push_back({v, level[v]});
  return paint;
}

void ApplyPaint(const Paint& paint, Tin& tin, bool apply_levels) {
  assert(paint.visible.size() == tin.triangles.size() && paint.tag.size() == tin.triangles.size());
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    tin.triangles[t].visible = paint.visible[t] != 0;
    tin.triangles[t].tag = paint.tag[t];
  }
  if (!apply_levels) return;
  for (const VertexLevel& level : paint.levels) tin.vertices[level.vertex].z = level.z;
}

}  // namespace tinbase
