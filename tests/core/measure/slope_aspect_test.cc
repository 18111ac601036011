// Slope and aspect against planes facing each way (exact), a flat plane (no aspect), height
// units, a geographic frame, and a paraboloid (slope atan(2 r), converging).
#include "core/measure/slope_aspect.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/core/measure/analytic_tins.h"

namespace tinbase {
namespace {

using testing::GridTin;
using testing::Paraboloid;

constexpr double kDeg = 180 / std::numbers::pi;

TEST(SlopeAspectTest, PlanesFacingEachWay) {
  struct Case {
    double gx, gy, aspect;
  };
  // The aspect is the downhill direction, clockwise from north.
  for (const Case& c : {Case{0, -1, 0}, Case{-1, 0, 90}, Case{0, 1, 180}, Case{1, 0, 270},
                        Case{0.3, -0.4, 360 + std::atan2(-0.3, 0.4) * kDeg}}) {
    const Tin tin =
        GridTin(3, 2, 0, 0, 6, 4, [&](double x, double y) { return c.gx * x + c.gy * y; });
    const auto slopes = SlopeAndAspect(tin, MetricFrame::Projected(), true);
    ASSERT_EQ(slopes.size(), tin.triangles.size());
    for (const TriangleSlope& s : slopes) {
      EXPECT_NEAR(s.slope_degrees, std::atan(std::hypot(c.gx, c.gy)) * kDeg, 1e-12);
      ASSERT_TRUE(s.aspect_degrees.has_value());
      EXPECT_NEAR(*s.aspect_degrees, c.aspect, 1e-12) << c.gx << " " << c.gy;
    }
  }
}

TEST(SlopeAspectTest, FlatHasNoAspectAndHiddenAreLeftOut) {
  Tin tin = GridTin(2, 2, 0, 0, 1, 1, [](double, double) { return 7; });
  tin.triangles[3].visible = false;
  const auto slopes = SlopeAndAspect(tin, MetricFrame::Projected(), true);
  ASSERT_EQ(slopes.size(), tin.triangles.size() - 1);
  for (const TriangleSlope& s : slopes) {
    EXPECT_NE(s.triangle, 3u);
    EXPECT_EQ(s.slope_degrees, 0);
    EXPECT_FALSE(s.aspect_degrees.has_value());
  }
  EXPECT_EQ(SlopeAndAspect(tin, MetricFrame::Projected(), false).size(), tin.triangles.size());
}

// Plan in metres and heights in feet: a rise of 1 unit per metre is 0.3048.
TEST(SlopeAspectTest, HeightUnitsCount) {
  const Tin tin = GridTin(1, 1, 0, 0, 1, 1, [](double x, double) { return x; });
  const auto slopes = SlopeAndAspect(tin, MetricFrame::Projected(1, 0.3048), true);
  EXPECT_NEAR(slopes[0].slope_degrees, std::atan(0.3048) * kDeg, 1e-12);
}

// Longitude / latitude: a surface rising 1 m per 111 m northwards (about 0.001 degree) near the
// equator on a sphere faces south at about atan(1 / 111.2).
TEST(SlopeAspectTest, GeographicFrameIsMetric) {
  const double radius = 6371000;
  const double metres_per_degree = radius * std::numbers::pi / 180;
  const Tin tin = GridTin(2, 2, 10, 0, 10.001, 0.001,
                          [&](double, double lat) { return lat * metres_per_degree / 100; });
  const auto slopes = SlopeAndAspect(tin, MetricFrame::Geographic({radius, 0}), true);
  for (const TriangleSlope& s : slopes) {
    EXPECT_NEAR(s.slope_degrees, std::atan(0.01) * kDeg, 1e-5);
    EXPECT_NEAR(*s.aspect_degrees, 180, 1e-3);
  }
}

// z = x^2 + y^2: the gradient at the centroid is 2 (x, y), facing the origin. A triangle's
// plane matches the gradient at each edge's midpoint along that edge (exact for a quadratic), so
// it differs from the gradient at the centroid by O(h): the error halves with the cell size.
TEST(SlopeAspectTest, ParaboloidConverges) {
  double last_error = 0;
  for (int n : {8, 16, 32, 64}) {
    const Tin tin = GridTin(n, n, 0.5, 0.5, 1.5, 1.5, Paraboloid);
    double error = 0;
    for (const TriangleSlope& s : SlopeAndAspect(tin, MetricFrame::Projected(), true)) {
      double cx = 0, cy = 0;
      for (uint32_t v : tin.triangles[s.triangle].v) {
        cx += tin.vertices[v].x / 3, cy += tin.vertices[v].y / 3;
      }
      const double slope = std::atan(2 * std::hypot(cx, cy)) * kDeg;
      const double aspect = std::atan2(-cx, -cy) * kDeg + 360;
      error = std::max(
          {error, std::abs(s.slope_degrees - slope), std::abs(*s.aspect_degrees - aspect)});
    }
    SCOPED_TRACE(n);
    EXPECT_LT(error, 20.0 / n);
    if (last_error > 0) {
      EXPECT_LT(error, last_error * 0.6);
    }
    last_error = error;
  }
}

}  // namespace
}  // namespace tinbase
