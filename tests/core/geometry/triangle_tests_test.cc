// SegmentMeetsTriangle, StrictlyInside and CircleHoldsAny on exact boundary cases: touching at a
// corner or along an edge counts as meeting, a point on an edge is not strictly inside, a point on
// the circumcircle is not held.
#include "core/geometry/triangle_tests.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace tinbase {
namespace {

const TriangleCorners kTri = {Point2{0, 0}, Point2{4, 0}, Point2{0, 4}};

bool Meets(const Point2& p, const Point2& q) {
  return SegmentMeetsTriangle(p, q, kTri[0], kTri[1], kTri[2]);
}

TEST(SegmentMeetsTriangle, CrossingInsideTouchingAndApart) {
  EXPECT_TRUE(Meets({-1, 1}, {5, 1}));   // crosses two edges
  EXPECT_TRUE(Meets({1, 1}, {1.5, 1}));  // wholly inside
  EXPECT_TRUE(Meets({-1, -1}, {0, 0}));  // ends on a corner
  EXPECT_TRUE(Meets({2, 2}, {3, 3}));    // starts on the hypotenuse
  EXPECT_TRUE(Meets({-1, 0}, {5, 0}));   // runs along an edge
  EXPECT_FALSE(Meets({3, 3}, {5, 5}));   // beyond the hypotenuse
  EXPECT_FALSE(Meets({-2, 1}, {-1, 3}));
  EXPECT_FALSE(Meets({5, -1}, {-1, -1}));  // below, parallel to an edge
  // One ulp beyond the hypotenuse x + y = 4 is apart; on it is not.
  EXPECT_FALSE(Meets({2, std::nextafter(2.0, 3.0)}, {5, 5}));
}

TEST(StrictlyInside, EdgesAndCornersAreNotInside) {
  EXPECT_TRUE(StrictlyInside(kTri, {1, 1}));
  EXPECT_FALSE(StrictlyInside(kTri, {2, 2}));  // on the hypotenuse
  EXPECT_FALSE(StrictlyInside(kTri, {0, 1}));  // on an edge
  EXPECT_FALSE(StrictlyInside(kTri, {4, 0}));  // a corner
  EXPECT_TRUE(StrictlyInside(kTri, {2, std::nextafter(2.0, 0.0)}));
  EXPECT_FALSE(StrictlyInside(kTri, {5, 5}));
}

TEST(CircleHoldsAny, OnlyPointsStrictlyInsideTheCircumcircle) {
  // The circumcircle of kTri: centre (2, 2), radius sqrt(8); (4, 4) lies on it.
  std::vector<Point2> on = {{4, 4}, {-10, 0}, {10, 0}};
  std::sort(on.begin(), on.end(), [](const Point2& a, const Point2& b) { return a.x < b.x; });
  EXPECT_FALSE(CircleHoldsAny(kTri, on));
  std::vector<Point2> inside = on;
  inside.push_back({std::nextafter(4.0, 0.0), 4});
  std::sort(inside.begin(), inside.end(),
            [](const Point2& a, const Point2& b) { return a.x < b.x; });
  EXPECT_TRUE(CircleHoldsAny(kTri, inside));
  EXPECT_FALSE(CircleHoldsAny(kTri, {}));
  // Far from the origin the double circumcentre rounds; the exact test still decides.
  const TriangleCorners far = {Point2{600000, 5100000}, Point2{600004, 5100000},
                               Point2{600000, 5100004}};
  EXPECT_FALSE(CircleHoldsAny(far, {{600004, 5100004}}));
  EXPECT_TRUE(CircleHoldsAny(far, {{600003.5, 5100003.5}}));
}

}  // namespace
}  // namespace tinbase
