#include "core/geometry/predicates.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace tinbase {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

Kernel::Point_2 ToCgal(const Point2& p) { return {p.x, p.y}; }

}  // namespace

int Orientation(const Point2& a, const Point2& b, const Point2& c) {
  return static_cast<int>(CGAL::orientation(ToCgal(a), ToCgal(b), ToCgal(c)));
}

int InCircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  // ON_POSITIVE_SIDE of the oriented circle is its inside when a, b, c are counter-clockwise.
  return static_cast<int>(
      CGAL::side_of_oriented_circle(ToCgal(a), ToCgal(b), ToCgal(c), ToCgal(d)));
}

}  // namespace tinbase
