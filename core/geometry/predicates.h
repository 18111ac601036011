// Exact plan-view predicates: orientation of three points and the in-circle test.
//
// Every topological decision in tinbase (is a triangle counter-clockwise, which side of an edge
// a query point lies on, is an edge locally Delaunay) goes through these two functions, which
// defer to CGAL's filtered exact predicates on Epick: the sign is always the sign of the exact
// determinant of the double inputs, never a rounded one. Stateless; thread-safe.
#pragma once

namespace tinbase {

struct Point2 {
  double x = 0;
  double y = 0;
};

// +1 when a, b, c turn left (counter-clockwise), -1 when they turn right, 0 when collinear.
// REQUIRES: finite coordinates.
int Orientation(const Point2& a, const Point2& b, const Point2& c);

// +1 when d lies strictly inside the circle through a, b, c, -1 strictly outside, 0 on it.
// REQUIRES: a, b, c counter-clockwise (Orientation(a, b, c) > 0); finite coordinates.
int InCircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d);

}  // namespace tinbase
