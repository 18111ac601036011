#include "core/geometry/triangle_tests.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tinbase {

// No separating line among pq's and the triangle's edges.
bool SegmentMeetsTriangle(const Point2& p, const Point2& q, const Point2& a, const Point2& b,
                          const Point2& c) {
  const int oa = Orientation(p, q, a), ob = Orientation(p, q, b), oc = Orientation(p, q, c);
  if ((oa > 0 && ob > 0 && oc > 0) || (oa < 0 && ob < 0 && oc < 0)) return false;
  const Point2* v[3] = {&a, &b, &c};
  for (int i = 0; i < 3; ++i) {
    const Point2& x = *v[i];
    const Point2& y = *v[(i + 1) % 3];
    if (Orientation(x, y, p) < 0 && Orientation(x, y, q) < 0) return false;
  }
  return true;
}

bool StrictlyInside(const TriangleCorners& c, const Point2& p) {
  return Orientation(c[0], c[1], p) > 0 && Orientation(c[1], c[2], p) > 0 &&
         Orientation(c[2], c[0], p) > 0;
}

bool CircleHoldsAny(const TriangleCorners& c, const std::vector<Point2>& sorted_by_x) {
  // Circumcentre and radius in doubles only bound the candidates (with a relative and an absolute
  // margin for their round-off); InCircle decides exactly. A degenerate triangle scans them all.
  const double ax = c[0].x, ay = c[0].y;
  const double bx = c[1].x - ax, by = c[1].y - ay, cx = c[2].x - ax, cy = c[2].y - ay;
  const double d = 2 * (bx * cy - by * cx);
  double lo = -std::numeric_limits<double>::infinity(), hi = -lo;
  if (d != 0) {
    const double ux = (cy * (bx * bx + by * by) - by * (cx * cx + cy * cy)) / d;
    const double uy = (bx * (cx * cx + cy * cy) - cx * (bx * bx + by * by)) / d;
    const double r = std::hypot(ux, uy) * (1 + 1e-9) + 1e-9;
    lo = ax + ux - r, hi = ax + ux + r;
  }
  auto it = std::lower_bound(sorted_by_x.begin(), sorted_by_x.end(), lo,
                             [](const Point2& p, double x) { return p.x < x; });
  for (; it != sorted_by_x.end() && it->x <= hi; ++it)
    if (InCircle(c[0], c[1], c[2], *it) > 0) return true;
  return false;
}

}  // namespace tinbase
