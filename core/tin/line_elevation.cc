#include "core/tin/line_elevation.h"

#include <algorithm>
#include <cmath>

namespace tinbase {

namespace {

// Where the foot of p on segment ab lies, as a fraction of ab clamped to [0, 1].
double FootFraction(const Point2& p, const Point2& a, const Point2& b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double length2 = dx * dx + dy * dy;
  if (length2 == 0) return 0;
  return std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / length2, 0.0, 1.0);
}

double DistanceAt(const Point2& p, const Point2& a, const Point2& b, double t) {
  return std::hypot(a.x + t * (b.x - a.x) - p.x, a.y + t * (b.y - a.y) - p.y);
}

}  // namespace

LineElevation::LineElevation(std::vector<Line3> lines, double near) : near_(near) {
  for (const Line3& line : lines) {
    for (size_t i = 0; i + 1 < line.points.size(); ++i) {
      Segment s{line.points[i], line.points[i + 1], line.z[i], line.z[i + 1], line.feature};
      s.min_x = std::min(s.a.x, s.b.x), s.max_x = std::max(s.a.x, s.b.x);
      s.min_y = std::min(s.a.y, s.b.y), s.max_y = std::max(s.a.y, s.b.y);
      max_width_ = std::max(max_width_, s.max_x - s.min_x);
      segments_.push_back(s);
    }
  }
  std::sort(segments_.begin(), segments_.end(),
            [](const Segment& s, const Segment& t) { return s.min_x < t.min_x; });
}

template <typename Visit>
void LineElevation::ForEachNear(const Point2& p, double reach, const Visit& visit) const {
  // Segments starting (in x) after p.x + reach cannot come near; those starting before
  // p.x - reach - max_width_ end before p.x - reach.
  const auto first = std::lower_bound(segments_.begin(), segments_.end(), p.x - reach - max_width_,
                                      [](const Segment& s, double x) { return s.min_x < x; });
  for (auto it = first; it != segments_.end() && it->min_x <= p.x + reach; ++it) {
    if (it->max_x < p.x - reach || it->min_y > p.y + reach || it->max_y < p.y - reach) continue;
    visit(*it);
  }
}

std::optional<double> LineElevation::ZAt(const Point2& p) const {
  std::optional<double> z;
  int64_t feature = 0;
  ForEachNear(p, near_, [&](const Segment& s) {
    if (z && s.feature < feature) return;
    const double t = FootFraction(p, s.a, s.b);
    if (DistanceAt(p, s.a, s.b, t) > near_) return;
    // A vertex of the line keeps its own z exactly (t is 0 or 1 only up to round-off there).
    const double at = SamePoint(p, s.a)   ? s.za
                      : SamePoint(p, s.b) ? s.zb
                                          : s.za + t * (s.zb - s.za);
    if (z && s.feature == feature) return;  // the same line: its segments meet at a vertex
    z = at;
    feature = s.feature;
  });
  return z;
}

bool LineElevation::Near(const Point2& p, double distance) const {
  bool found = false;
  ForEachNear(p, distance, [&](const Segment& s) {
    if (!found) found = DistanceAt(p, s.a, s.b, FootFraction(p, s.a, s.b)) <= distance;
  });
  return found;
}

}  // namespace tinbase
