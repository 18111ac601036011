// Orientation and InCircle give the exact sign, also where a double formula rounds wrongly.
#include "core/geometry/predicates.h"

#include <gtest/gtest.h>

#include <cmath>

namespace tinbase {
namespace {

TEST(Orientation, LeftRightAndCollinear) {
  EXPECT_EQ(Orientation({0, 0}, {1, 0}, {0, 1}), 1);
  EXPECT_EQ(Orientation({0, 0}, {0, 1}, {1, 0}), -1);
  EXPECT_EQ(Orientation({0, 0}, {1, 1}, {3, 3}), 0);
}

TEST(Orientation, IsExactOneUlpFromCollinear) {
  // det((b - a), (c - a)) for a = (ax, 0.5), b = (12, 12), c = (24, 24) is 6 - 12 ax: zero at
  // ax = 0.5, and its sign flips one ulp either side, where the rounded double formula is noise.
  const Point2 b{12, 12}, c{24, 24};
  EXPECT_EQ(Orientation({0.5, 0.5}, b, c), 0);
  EXPECT_EQ(Orientation({std::nextafter(0.5, 1.0), 0.5}, b, c), -1);
  EXPECT_EQ(Orientation({std::nextafter(0.5, 0.0), 0.5}, b, c), 1);
  // Large map coordinates: three points on the line y = x + 4500000 stay collinear.
  EXPECT_EQ(Orientation({600000, 5100000}, {600001, 5100001}, {600003, 5100003}), 0);
  EXPECT_EQ(
      Orientation({600000, 5100000}, {600001, 5100001}, {600003, std::nextafter(5100003.0, 6e6)}),
      1);
}

TEST(InCircle, InsideOnAndOutsideTheUnitCircle) {
  const Point2 a{1, 0}, b{0, 1}, c{-1, 0};
  EXPECT_EQ(InCircle(a, b, c, {0, 0}), 1);
  EXPECT_EQ(InCircle(a, b, c, {0, -1}), 0);  // co-circular: a tie, as on a grid
  EXPECT_EQ(InCircle(a, b, c, {2, 0}), -1);
  EXPECT_EQ(InCircle(a, b, c, {0, std::nextafter(-1.0, 0.0)}), 1);
  EXPECT_EQ(InCircle(a, b, c, {0, std::nextafter(-1.0, -2.0)}), -1);
}

TEST(InCircle, GridSquareCornersAreTies) {
  const Point2 a{600000, 5100000}, b{600030, 5100000}, c{600030, 5100030};
  EXPECT_EQ(InCircle(a, b, c, {600000, 5100030}), 0);
  EXPECT_EQ(InCircle(a, b, c, {600001, 5100029}), 1);
}

}  // namespace
}  // namespace tinbase
