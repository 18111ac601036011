#include "core/geometry/segment_index.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tinbase {
namespace {

struct Bounds {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -std::numeric_limits<double>::infinity(), max_y = max_x;
  void Add(const Point2& p) {
    min_x = std::min(min_x, p.x), min_y = std::min(min_y, p.y);
    max_x = std::max(max_x, p.x), max_y = std::max(max_y, p.y);
  }
  bool Contains(const Point2& p) const {
    return p.x >= min_x && p.x <= max_x && p.y >= min_y && p.y <= max_y;
  }
};

Bounds BoundsOf(const Point2& a, const Point2& b) {
  Bounds s;
  s.Add(a), s.Add(b);
  return s;
}

}  // namespace

void SegmentIndex::Build(std::vector<std::pair<Point2, Point2>> segments) {
  segments_ = std::move(segments);
  Bounds all;
  for (const auto& [a, b] : segments_) all.Add(a), all.Add(b);
  min_x_ = all.min_x, min_y_ = all.min_y, max_x_ = all.max_x, max_y_ = all.max_y;
  side_ = std::max<int64_t>(1, static_cast<int64_t>(std::sqrt(segments_.size())));
  cells_.assign(static_cast<size_t>(side_ * side_), {});
  for (uint32_t k = 0; k < segments_.size(); ++k) {
    const Bounds b = BoundsOf(segments_[k].first, segments_[k].second);
    for (int64_t r = Row(b.min_y); r <= Row(b.max_y); ++r)
      for (int64_t c = Col(b.min_x); c <= Col(b.max_x); ++c) cells_[r * side_ + c].push_back(k);
  }
}

bool SegmentIndex::OnAny(const Point2& p) const {
  if (!(p.x >= min_x_ && p.x <= max_x_ && p.y >= min_y_ && p.y <= max_y_)) return false;
  for (uint32_t k : cells_[Row(p.y) * side_ + Col(p.x)]) {
    const auto& [a, b] = segments_[k];
    if (BoundsOf(a, b).Contains(p) && Orientation(a, b, p) == 0) return true;
  }
  return false;
}

int64_t SegmentIndex::Index(double v, double lo, double hi) const {
  if (!(hi > lo)) return 0;
  return std::clamp<int64_t>(static_cast<int64_t>((v - lo) / (hi - lo) * side_), 0, side_ - 1);
}

}  // namespace tinbase
