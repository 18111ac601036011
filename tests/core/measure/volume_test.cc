// Volumes against known integrals: a plane against a level and inside a polygon (exact), a
// paraboloid against a level (converging), two planes triangulated differently (exact), a
// paraboloid under a plane inside a polygon (converging); the exact split of one triangle; and
// the bad inputs: a level that is not a number, surfaces that do not overlap.
#include "core/measure/volume.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "tests/core/measure/analytic_tins.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::GridTin;
using testing::Paraboloid;

const MetricFrame kMetres = MetricFrame::Projected();

Polygon Square(double x0, double y0, double x1, double y1) {
  return {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, {}};
}

TEST(LevelSplitTest, CornerCasesAndTotals) {
  // All above, all below, one corner on zero.
  SplitMeasure s = SplitTriangle(2, {1, 2, 3});
  EXPECT_DOUBLE_EQ(s.above_volume, 4);
  EXPECT_DOUBLE_EQ(s.above_area, 2);
  EXPECT_EQ(s.below_volume, 0);
  s = SplitTriangle(2, {0, -3, -3});
  EXPECT_EQ(s.above_volume, 0);
  EXPECT_EQ(s.above_area, 0);
  EXPECT_DOUBLE_EQ(s.below_volume, 4);
  // One corner up by 1, two down by 1: the zero line halves the two edges from the lone corner,
  // leaving a quarter of the area above, as a pyramid of height 1.
  s = SplitTriangle(4, {1, -1, -1});
  EXPECT_DOUBLE_EQ(s.above_area, 1);
  EXPECT_DOUBLE_EQ(s.above_volume, 1.0 / 3);
  EXPECT_DOUBLE_EQ(s.below_area, 3);
  EXPECT_DOUBLE_EQ(s.above_volume - s.below_volume, 4 * (1 - 1 - 1) / 3.0);
  // Two corners on zero: the triangle lies on one side.
  s = SplitTriangle(3, {0, 0, 2});
  EXPECT_DOUBLE_EQ(s.above_volume, 2);
  EXPECT_DOUBLE_EQ(s.above_area, 3);
  EXPECT_EQ(s.below_area, 0);
}

// z = 1 + x / 2 over [0, 4] x [0, 2] (z from 1 to 3) against level 2: 2 m3 above over 4 m2 and
// 2 m3 below over 4 m2.
TEST(VolumeTest, PlaneAgainstALevelIsExact) {
  const Tin tin = GridTin(5, 3, 0, 0, 4, 2, [](double x, double) { return 1 + x / 2; });
  auto v = VolumeAgainstLevel(tin, 2, kMetres);
  ASSERT_TRUE(v.ok()) << v.status().ToString();
  EXPECT_NEAR(v->split.above_volume, 2, 1e-12);
  EXPECT_NEAR(v->split.below_volume, 2, 1e-12);
  EXPECT_NEAR(v->split.above_area, 4, 1e-12);
  EXPECT_NEAR(v->split.below_area, 4, 1e-12);
  EXPECT_NEAR(v->plan_area, 8, 1e-12);
  v = VolumeAgainstLevel(tin, 0, kMetres);
  ASSERT_TRUE(v.ok());
  EXPECT_NEAR(v->split.above_volume, 16, 1e-12);
  EXPECT_EQ(v->split.below_volume, 0);
  v = VolumeAgainstLevel(tin, 10, kMetres);
  ASSERT_TRUE(v.ok());
  EXPECT_NEAR(v->split.below_volume, 80 - 16, 1e-12);
}

// Inside [1, 3] x [0.5, 1.5] less the hole [1.5, 2.5] x [0.75, 1.25], against level 0: the
// integral of 1 + x / 2 over the square (4) minus over the hole (0.5 * 2 = 1).
TEST(VolumeTest, PlaneInsideAPolygonWithAHoleIsExact) {
  const Tin tin = GridTin(5, 3, 0, 0, 4, 2, [](double x, double) { return 1 + x / 2; });
  Polygon p = Square(1, 0.5, 3, 1.5);
  p.holes.push_back({{1.5, 0.75}, {1.5, 1.25}, {2.5, 1.25}, {2.5, 0.75}});
  auto region = PlanRegion::FromPolygons({p});
  ASSERT_TRUE(region.ok()) << region.status().ToString();
  EXPECT_NEAR(region->Area(), 1.5, 1e-12);
  auto v = VolumeAgainstLevel(tin, 0, kMetres, &*region);
  ASSERT_TRUE(v.ok()) << v.status().ToString();
  EXPECT_NEAR(v->split.above_volume, 3, 1e-12);
  EXPECT_NEAR(v->plan_area, 1.5, 1e-12);
}

// z = x^2 + y^2 over [-1, 1]^2 against level 1: below, the unit disc holds pi / 2; above, the
// total 8 / 3 - 4 plus that. The TIN over-estimates a convex surface by O(h^2).
TEST(VolumeTest, ParaboloidAgainstALevelConverges) {
  const double below = std::numbers::pi / 2;
  const double above = 8.0 / 3 - 4 + below;
  double last_error = 1;
  for (int n : {8, 16, 32, 64}) {
    const Tin tin = GridTin(n, n, -1, -1, 1, 1, Paraboloid);
    auto v = VolumeAgainstLevel(tin, 1, kMetres);
    ASSERT_TRUE(v.ok());
    const double error =
        std::abs(v->split.below_volume - below) + std::abs(v->split.above_volume - above);
    SCOPED_TRACE(n);
    EXPECT_LT(error, 6.0 / (n * n));
    EXPECT_LT(error, last_error / 3);
    EXPECT_NEAR(v->split.below_area, std::numbers::pi, 8.0 / (n * n));
    last_error = error;
  }
}

TEST(VolumeTest, LevelMustBeANumber) {
  const Tin tin = GridTin(2, 2, 0, 0, 1, 1, Paraboloid);
  for (double level :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    auto v = VolumeAgainstLevel(tin, level, kMetres);
    ASSERT_FALSE(v.ok());
    EXPECT_EQ(v.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(v.status().message().find("level must be a finite number"), std::string::npos)
        << v.status().message();
  }
  auto v = VolumeAgainstLevel(tin, std::numeric_limits<double>::quiet_NaN(), kMetres);
  EXPECT_NE(v.status().message().find("nan"), std::string::npos) << v.status().message();
}

// Base z = 0 over [0, 2]^2, top z = x - 1.5 over [1, 3] x [0, 2], triangulated differently: over
// the common [1, 2] x [0, 2] the top is below from 1 to 1.5 and above from 1.5 to 2, each a
// wedge of 0.25 m3 over 1 m2.
TEST(VolumeTest, TwoPlanesTriangulatedDifferentlyAreExact) {
  const Tin base = GridTin(3, 3, 0, 0, 2, 2, [](double, double) { return 0; });
  const Tin top = GridTin(5, 4, 1, 0, 3, 2, [](double x, double) { return x - 1.5; });
  auto v = VolumeBetween(base, top, kMetres);
  ASSERT_TRUE(v.ok()) << v.status().ToString();
  EXPECT_NEAR(v->plan_area, 2, 1e-12);
  EXPECT_NEAR(v->split.above_volume, 0.25, 1e-12);  // fill
  EXPECT_NEAR(v->split.below_volume, 0.25, 1e-12);  // cut
  EXPECT_NEAR(v->split.above_area, 1, 1e-12);
  EXPECT_NEAR(v->split.below_area, 1, 1e-12);
  // Swapping the surfaces swaps cut and fill.
  auto w = VolumeBetween(top, base, kMetres);
  ASSERT_TRUE(w.ok());
  EXPECT_NEAR(w->split.above_volume, v->split.below_volume, 1e-12);
}

// Base z = x^2 + y^2, top the plane z = 1 (two triangles), inside [-0.5, 0.5]^2: the fill is
// 1 - 1/6 = 5/6.
TEST(VolumeTest, ParaboloidUnderAPlaneInsideAPolygonConverges) {
  const Tin top = GridTin(1, 1, -2, -2, 2, 2, [](double, double) { return 1; });
  auto region = PlanRegion::FromPolygons({Square(-0.5, -0.5, 0.5, 0.5)});
  ASSERT_TRUE(region.ok());
  double last_error = 1;
  for (int n : {6, 12, 24, 48}) {
    const Tin base = GridTin(n, n, -1, -1, 1, 1, Paraboloid);
    auto v = VolumeBetween(base, top, kMetres, &*region);
    ASSERT_TRUE(v.ok()) << v.status().ToString();
    SCOPED_TRACE(n);
    EXPECT_NEAR(v->plan_area, 1, 1e-12);
    EXPECT_EQ(v->split.below_volume, 0);
    const double error = std::abs(v->split.above_volume - 5.0 / 6);
    EXPECT_LT(error, 1.5 / (n * n));
    EXPECT_LT(error, last_error / 3);
    last_error = error;
  }
}

TEST(VolumeTest, SurfacesThatDoNotOverlapAreAnError) {
  const Tin a = GridTin(2, 2, 0, 0, 1, 1, Paraboloid);
  const Tin b = GridTin(2, 2, 5, 5, 6, 6, Paraboloid);
  auto v = VolumeBetween(a, b, kMetres);
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(v.status().message(), "the surfaces do not overlap");
  // Overlapping, but not inside the polygon.
  auto region = PlanRegion::FromPolygons({Square(2, 2, 3, 3)});
  ASSERT_TRUE(region.ok());
  v = VolumeBetween(a, a, kMetres, &*region);
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.status().message(), "the surfaces do not overlap inside the polygon");
  // Overlapping only where one is hidden.
  Tin hidden = a;
  for (TinTriangle& t : hidden.triangles) t.visible = false;
  EXPECT_FALSE(VolumeBetween(a, hidden, kMetres).ok());
  EXPECT_FALSE(VolumeAgainstLevel(hidden, 0, kMetres).ok());
}

// The signed volume of a surface over a region, from VolumeAgainstLevel.
double Integral(const Tin& tin, const PlanRegion* region) {
  auto v = VolumeAgainstLevel(tin, 0, kMetres, region);
  RC_ASSERT(v.ok());
  return v->split.above_volume - v->split.below_volume;
}

// Two differently triangulated, randomly perturbed grids over the same 600 m square, the second
// raised by a random offset: fill - cut between them is the difference of their own integrals
// (over the square, and inside a random rectangle), so the overlay loses and doubles nothing.
RC_GTEST_PROP(VolumeProperty, BetweenIsTheDifferenceOfIntegrals, ()) {
  const auto seed = *rc::gen::arbitrary<uint32_t>();
  Tin a = testing::PerturbedGridTin(31, 31, seed, 20, 0.3);
  Tin b = testing::PerturbedGridTin(21, 21, seed + 1, 30, 0.3);
  const double offset = *rc::gen::inRange(-50, 50);
  for (TinVertex& v : b.vertices) v.z += offset;
  auto v = VolumeBetween(a, b, kMetres);
  RC_ASSERT(v.ok());
  RC_ASSERT(std::abs(v->plan_area - 360000) < 1e-6);
  const double want = Integral(b, nullptr) - Integral(a, nullptr);
  const double net = v->split.above_volume - v->split.below_volume;
  RC_ASSERT(std::abs(net - want) <= 1e-9 * (v->split.above_volume + v->split.below_volume) + 1e-6);
  const double x0 = 600000 + *rc::gen::inRange(0, 300), y0 = 5100000 + *rc::gen::inRange(0, 300);
  const double w = *rc::gen::inRange(1, 300), h = *rc::gen::inRange(1, 300);
  auto region = PlanRegion::FromPolygons({Square(x0, y0, x0 + w, y0 + h)});
  RC_ASSERT(region.ok());
  auto inside = VolumeBetween(a, b, kMetres, &*region);
  RC_ASSERT(inside.ok());
  RC_ASSERT(std::abs(inside->plan_area - w * h) < 1e-6);
  const double want_inside = Integral(b, &*region) - Integral(a, &*region);
  const double net_inside = inside->split.above_volume - inside->split.below_volume;
  RC_ASSERT(std::abs(net_inside - want_inside) <=
            1e-9 * (inside->split.above_volume + inside->split.below_volume) + 1e-6);
}

TEST(PlanRegionTest, NoPolygonIsAnError) {
  auto region = PlanRegion::FromPolygons({});
  ASSERT_FALSE(region.ok());
  EXPECT_EQ(region.status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace tinbase
