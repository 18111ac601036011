// MeasureArea against surfaces with known areas: a tilted plane (exact), a paraboloid over a
// disc (its integral, closer as the triangulation is refined), tags and hidden triangles, and
// geodesic areas of a latitude band on a sphere.
#include "core/measure/surface_area.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/core/measure/analytic_tins.h"

namespace tinbase {
namespace {

using testing::DiscTin;
using testing::GridTin;
using testing::Paraboloid;

TEST(SurfaceAreaTest, TiltedPlaneIsExact) {
  const Tin tin =
      GridTin(7, 9, 0, 0, 10, 20, [](double x, double y) { return 2 + 0.3 * x - 0.4 * y; });
  const AreaReport r = MeasureArea(tin, MetricFrame::Projected());
  EXPECT_FALSE(r.geodesic);
  EXPECT_EQ(r.total.triangles, 7 * 9 * 2);
  EXPECT_NEAR(r.total.plan, 200, 1e-10);
  EXPECT_NEAR(r.total.surface, 200 * std::sqrt(1.25), 1e-10);
  ASSERT_EQ(r.tags.size(), 1u);
  EXPECT_FALSE(r.tags[0].tag.has_value());
}

// Units: feet in plan and in height scale areas by the square of a foot.
TEST(SurfaceAreaTest, UnitsBecomeMetres) {
  const Tin tin = GridTin(2, 2, 0, 0, 10, 10, [](double x, double) { return x; });
  const AreaReport r = MeasureArea(tin, MetricFrame::Projected(0.3048, 0.3048));
  EXPECT_NEAR(r.total.plan, 100 * 0.3048 * 0.3048, 1e-10);
  EXPECT_NEAR(r.total.surface, 100 * 0.3048 * 0.3048 * std::sqrt(2.0), 1e-10);
}

TEST(SurfaceAreaTest, PerTagAndOnlyVisible) {
  Tin tin = GridTin(4, 4, 0, 0, 4, 4, [](double, double) { return 5; });
  tin.tags = {"granite", "basalt"};
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    if (t < 8) tin.triangles[t].tag = 0;             // 4 cells of granite
    if (t >= 8 && t < 12) tin.triangles[t].tag = 1;  // 2 cells of basalt
    if (t >= 28) tin.triangles[t].visible = false;   // 2 cells hidden
  }
  const AreaReport r = MeasureArea(tin, MetricFrame::Projected());
  EXPECT_EQ(r.total.triangles, 28);
  EXPECT_NEAR(r.total.plan, 14, 1e-12);
  ASSERT_EQ(r.tags.size(), 3u);
  EXPECT_EQ(r.tags[0].tag, "basalt");
  EXPECT_NEAR(r.tags[0].area.plan, 2, 1e-12);
  EXPECT_EQ(r.tags[1].tag, "granite");
  EXPECT_NEAR(r.tags[1].area.surface, 4, 1e-12);
  EXPECT_FALSE(r.tags[2].tag.has_value());
  EXPECT_EQ(r.tags[2].area.triangles, 16);
  EXPECT_NEAR(r.tags[2].area.plan, 8, 1e-12);
}

// z = x^2 + y^2 over the unit disc: plan area pi, surface area pi / 6 (5 sqrt 5 - 1). The
// inscribed TIN converges at second order.
TEST(SurfaceAreaTest, ParaboloidConverges) {
  const double plan = std::numbers::pi;
  const double surface = std::numbers::pi / 6 * (5 * std::sqrt(5.0) - 1);
  double last_error = 1;
  for (int rings : {8, 16, 32}) {
    const AreaReport r = MeasureArea(DiscTin(rings, 1, Paraboloid), MetricFrame::Projected());
    const double error = std::abs(r.total.surface - surface) / surface;
    const double plan_error = std::abs(r.total.plan - plan) / plan;
    SCOPED_TRACE(rings);
    EXPECT_LT(plan_error, 0.5 / (rings * rings));
    EXPECT_LT(error, 1.0 / (rings * rings));
    EXPECT_LT(error, last_error / 3);  // about 4x smaller per halving
    last_error = error;
  }
  EXPECT_LT(last_error, 1e-3);
}

// A band 1 degree of longitude wide between latitudes 40 and 41 on a sphere of radius R has area
// R^2 (pi / 180) (sin 41 - sin 40). Triangles have geodesic edges, so the band's parallels are
// approximated by chords; the error shrinks as the grid is refined.
TEST(SurfaceAreaTest, GeodesicAreaOfALatitudeBand) {
  const double radius = 6371000;
  const double d = std::numbers::pi / 180;
  const double want = radius * radius * d * (std::sin(41 * d) - std::sin(40 * d));
  const MetricFrame sphere = MetricFrame::Geographic({radius, 0});
  double last_error = 1;
  for (int n : {2, 4, 8}) {
    const Tin tin = GridTin(n, n, 10, 40, 11, 41, [](double, double) { return 0; });
    const AreaReport r = MeasureArea(tin, sphere);
    EXPECT_TRUE(r.geodesic);
    const double error = std::abs(r.total.plan - want) / want;
    SCOPED_TRACE(n);
    EXPECT_LT(error, last_error / 3);
    last_error = error;
    // Flat ground: the 3D area is the area of the plane triangles, a hair below the curved one.
    EXPECT_NEAR(r.total.surface / r.total.plan, 1, 1e-4);
  }
  EXPECT_LT(last_error, 1e-6);
}

TEST(SurfaceAreaTest, StoreCrsGivesTheFrame) {
  auto wgs84 = Crs::FromUserInput("EPSG:4326");
  ASSERT_TRUE(wgs84.ok());
  auto frame = MetricFrameFor(&*wgs84);
  ASSERT_TRUE(frame.ok()) << frame.status().ToString();
  ASSERT_TRUE(frame->geographic());
  EXPECT_DOUBLE_EQ(frame->ellipsoid()->a, 6378137.0);
  EXPECT_NEAR(1 / frame->ellipsoid()->f, 298.257223563, 1e-9);
  auto utm = Crs::FromUserInput("EPSG:32632");
  ASSERT_TRUE(utm.ok());
  frame = MetricFrameFor(&*utm);
  ASSERT_TRUE(frame.ok());
  EXPECT_FALSE(frame->geographic());
  auto feet = Crs::FromUserInput("EPSG:2227");  // California zone 3, US survey feet
  ASSERT_TRUE(feet.ok());
  frame = MetricFrameFor(&*feet);
  ASSERT_TRUE(frame.ok());
  const Tin square = GridTin(1, 1, 0, 0, 1, 1, [](double, double) { return 0; });
  EXPECT_NEAR(MeasureArea(square, *frame).total.plan, std::pow(1200.0 / 3937, 2), 1e-12);
}

}  // namespace
}  // namespace tinbase
