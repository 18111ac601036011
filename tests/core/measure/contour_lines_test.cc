// Contour lines against known ones: straight lines on a plane (exact, one polyline each, high
// ground on the right), circles on a paraboloid (closed, joined across every triangle, radius
// converging) and arcs cut by the boundary (open); then the bad intervals.
#include "core/measure/contour_lines.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "core/geometry/polygon.h"
#include "tests/core/measure/analytic_tins.h"

namespace tinbase {
namespace {

using testing::GridTin;
using testing::Paraboloid;

double Length(const ContourLine& line) {
  double sum = 0;
  const size_t n = line.points.size();
  for (size_t i = 0; i + 1 < n + (line.closed ? 1 : 0); ++i) {
    const Point2& p = line.points[i];
    const Point2& q = line.points[(i + 1) % n];
    sum += std::hypot(q.x - p.x, q.y - p.y);
  }
  return sum;
}

// z = x over [0, 10] x [0, 4]: the level k + 0.5 is the line x = k + 0.5 from south to north
// (higher ground, east, on the right), one polyline across the 8 rows of triangles.
TEST(ContourLinesTest, PlaneGivesStraightLines) {
  const Tin tin = GridTin(10, 4, 0, 0, 10, 4, [](double x, double) { return x; });
  auto lines = TraceContours(tin, {.interval = 1, .base = 0.5});
  ASSERT_TRUE(lines.ok()) << lines.status().ToString();
  ASSERT_EQ(lines->size(), 10u);
  for (size_t k = 0; k < 10; ++k) {
    const ContourLine& line = (*lines)[k];
    EXPECT_EQ(line.level, static_cast<double>(k) + 0.5);
    EXPECT_FALSE(line.closed);
    for (const Point2& p : line.points) EXPECT_NEAR(p.x, line.level, 1e-12);
    EXPECT_EQ(line.points.front().y, 0);
    EXPECT_EQ(line.points.back().y, 4);
    EXPECT_NEAR(Length(line), 4, 1e-12);
  }
}

// z = x^2 + y^2 over [-1, 1]^2 at level 0.25: one closed line, the circle of radius 0.5, walked
// counter-clockwise (the higher ground outside on the right). Its vertices lie on the TIN's edges,
// where the TIN over-estimates z by O(h^2), so they sit inside the circle by that much.
TEST(ContourLinesTest, ParaboloidGivesAClosedCircle) {
  double last_error = 1;
  for (int n : {8, 16, 32, 64}) {
    const Tin tin = GridTin(n, n, -1, -1, 1, 1, Paraboloid);
    auto lines = TraceContours(tin, {.interval = 0.25});
    ASSERT_TRUE(lines.ok()) << lines.status().ToString();
    std::vector<ContourLine> at_quarter;
    for (const ContourLine& line : *lines) {
      if (line.level == 0.25) at_quarter.push_back(line);
    }
    SCOPED_TRACE(n);
    ASSERT_EQ(at_quarter.size(), 1u);
    const ContourLine& circle = at_quarter[0];
    EXPECT_TRUE(circle.closed);
    EXPECT_GT(SignedDoubleArea(circle.points), 0);  // counter-clockwise
    double error = 0;
    for (const Point2& p : circle.points)
      error = std::max(error, std::abs(std::hypot(p.x, p.y) - 0.5));
    EXPECT_LT(error, 2.0 / (n * n));
    EXPECT_LT(error, last_error);
    last_error = error;
    EXPECT_NEAR(Length(circle), std::numbers::pi, 10.0 / (n * n));
  }
}

// At level 1.5 the circle of radius 1.22 leaves the square: four open arcs, one per corner.
TEST(ContourLinesTest, LinesCutByTheBoundaryStayOpen) {
  const Tin tin = GridTin(16, 16, -1, -1, 1, 1, Paraboloid);
  auto lines = TraceContours(tin, {.interval = 1.5});
  ASSERT_TRUE(lines.ok());
  ASSERT_EQ(lines->size(), 4u);
  for (const ContourLine& line : *lines) {
    EXPECT_EQ(line.level, 1.5);
    EXPECT_FALSE(line.closed);
    for (const Point2& p : {line.points.front(), line.points.back()}) {
      EXPECT_NEAR(std::max(std::abs(p.x), std::abs(p.y)), 1, 1e-12);  // on the boundary
    }
  }
}

// A hidden triangle is a gap: the circle through it is cut open there.
TEST(ContourLinesTest, HiddenTrianglesCutLines) {
  Tin tin = GridTin(16, 16, -1, -1, 1, 1, Paraboloid);
  size_t hidden = 0;
  for (TinTriangle& t : tin.triangles) {
    double cx = 0, cy = 0;
    for (uint32_t v : t.v) cx += tin.vertices[v].x / 3, cy += tin.vertices[v].y / 3;
    if (cx > 0.4 && cx < 0.6 && std::abs(cy) < 0.1) t.visible = false, ++hidden;
  }
  ASSERT_GT(hidden, 0u);
  auto lines = TraceContours(tin, {.interval = 0.25});
  ASSERT_TRUE(lines.ok());
  size_t at_quarter = 0;
  for (const ContourLine& line : *lines) {
    if (line.level != 0.25) continue;
    ++at_quarter;
    EXPECT_FALSE(line.closed);
  }
  EXPECT_EQ(at_quarter, 1u);
}

TEST(ContourLinesTest, BadIntervalsAreRejected) {
  const Tin tin = GridTin(2, 2, 0, 0, 1, 1, [](double x, double) { return x; });
  for (double interval : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                          std::numeric_limits<double>::infinity()}) {
    auto lines = TraceContours(tin, {.interval = interval});
    ASSERT_FALSE(lines.ok()) << interval;
    EXPECT_NE(lines.status().message().find("contour interval must be a positive number"),
              std::string::npos)
        << lines.status().message();
  }
  auto lines = TraceContours(tin, {.interval = 1e-9});
  ASSERT_FALSE(lines.ok());
  EXPECT_NE(lines.status().message().find("levels between z 0 and 1"), std::string::npos)
      << lines.status().message();
  lines = TraceContours(tin, {.interval = 1, .base = std::numeric_limits<double>::quiet_NaN()});
  ASSERT_FALSE(lines.ok());
  EXPECT_NE(lines.status().message().find("base"), std::string::npos);
  // No level inside [0, 1] at interval 10 from base 2.
  lines = TraceContours(tin, {.interval = 10, .base = 2});
  ASSERT_FALSE(lines.ok());
  EXPECT_NE(lines.status().message().find("no contour line"), std::string::npos)
      << lines.status().message();
}

}  // namespace
}  // namespace tinbase
