// DEM from contours: the contour TIN's promises (no flat triangle left, contours kept as edges),
// exactness on a plane, the summit rule, the crossing rules, and the round trip DEM -> GDAL
// contours -> DEM on a real alpine DEM.
#include "core/raster/contour_dem.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>

#include "core/vector/polygon_source.h"
#include "tests/support/make_contours.h"
#include "tests/support/read_grid.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_checks.h"

namespace tinbase {
namespace {

using testing::DataPath;

constexpr double kPi = 3.14159265358979323846;

int64_t FlatTriangles(const Tin& tin) {
  int64_t flat = 0;
  for (const TinTriangle& t : tin.triangles) {
    const double z = tin.vertices[t.v[0]].z;
    flat += tin.vertices[t.v[1]].z == z && tin.vertices[t.v[2]].z == z;
  }
  return flat;
}

ContourLine Line(const std::string& label, double level, std::vector<Point2> points) {
  return ContourLine{label, level, std::move(points)};
}

// A circle of `n` points around (cx, cy), closed (last point = first).
std::vector<Point2> Circle(double cx, double cy, double r, int n, double phase = 0) {
  std::vector<Point2> points;
  for (int k = 0; k <= n; ++k) {
    const double a = 2 * kPi * (k % n) / n + phase;
    points.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
  }
  return points;
}

void ExpectValidContourTin(const Tin& tin) {
  testing::ExpectCounterClockwise(tin);
  testing::ExpectNeighboursConsistent(tin);
  testing::ExpectConstraintsAreEdges(tin);
  testing::ExpectLocallyDelaunay(tin);  // Steiner points are inserted as Delaunay points
  EXPECT_EQ(FlatTriangles(tin), 0);
}

TEST(ContourDem, StraightContoursOfAPlaneGiveThePlane) {
  // z = 100 + x / 10 has straight contours x = const; every triangle spans two neighbouring
  // contours, so linear interpolation is exact.
  std::vector<ContourLine> lines;
  for (int level = 100; level <= 200; level += 10) {
    const double x = (level - 100) * 10.0;
    std::vector<Point2> points;
    for (int k = 0; k <= 20; ++k) points.push_back({x, k * 50.0 + (level % 20 == 0 ? 0 : 25.0)});
    lines.push_back(Line("line " + std::to_string(level), level, points));
  }
  ContourDemReport report;
  auto grid = DemFromContours(lines, 20.0, &report);
  ASSERT_TRUE(grid.ok()) << grid.status().ToString();
  EXPECT_EQ(report.flat_triangles_found, 0);
  int64_t covered = 0;
  for (int64_t r = 0; r < grid->geometry.height; ++r) {
    for (int64_t c = 0; c < grid->geometry.width; ++c) {
      if (!grid->IsValid(c, r)) continue;
      ++covered;
      EXPECT_NEAR(grid->At(c, r), 100 + grid->geometry.CellCenterX(c) / 10, 1e-3);
    }
  }
  EXPECT_GT(covered, 2000);
}

TEST(ContourDem, ConeSummitRisesHalfAnIntervalAboveItsTopContour) {
  // Concentric contours of a cone; the innermost (level 140) encloses only flat triangles.
  std::vector<ContourLine> lines;
  for (int k = 0; k < 5; ++k) {
    lines.push_back(Line("ring " + std::to_string(k), 100 + 10 * k,
                         Circle(1000, 2000, 500 - 100 * k, 48, 0.05 * k)));
  }
  ContourDemReport report;
  auto tin = BuildContourTin(lines, &report);
  ASSERT_TRUE(tin.ok()) << tin.status().ToString();
  ExpectValidContourTin(*tin);
  EXPECT_GT(report.flat_triangles_found, 0);
  EXPECT_GT(report.steiner_points, 0);
  EXPECT_EQ(report.flat_triangles_left, 0);
  double top = 0;
  for (const TinVertex& v : tin->vertices) {
    if (v.kind != VertexKind::kSteiner) continue;
    EXPECT_GT(v.z, 100);
    EXPECT_LT(v.z, 150);  // never beyond half an interval above the top contour
    top = std::max(top, v.z);
  }
  EXPECT_GT(top, 140);  // the summit is above its enclosing contour
}

TEST(ContourDem, CrossingAndTouchingRules) {
  const auto a = Line("c.geojson feature 0", 100, {{0, 0}, {100, 100}});
  const auto b = Line("c.geojson feature 1", 200, {{0, 100}, {100, 0}});
  Status s = CheckContoursDoNotCross({a, b});
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("c.geojson feature 0 (level 100) and c.geojson feature 1 (level 200) "
                             "cross at (50, 50)"),
            std::string::npos)
      << s.message();
  // Same level: touching is fine, crossing is not.
  const auto b_same = Line("c.geojson feature 1", 100, {{0, 100}, {100, 0}});
  EXPECT_FALSE(CheckContoursDoNotCross({a, b_same}).ok());
  const auto touch_same = Line("t", 100, {{50, 50}, {100, 0}});
  EXPECT_TRUE(CheckContoursDoNotCross({a, touch_same}).ok());
  // Different levels may not even touch.
  const auto touch_other = Line("t", 150, {{50, 50}, {100, 0}});
  s = CheckContoursDoNotCross({a, touch_other});
  EXPECT_NE(s.message().find("touch at (50, 50)"), std::string::npos) << s.message();
  // A line crossing itself.
  const auto bow = Line("bow", 100, {{0, 0}, {100, 100}, {100, 0}, {0, 100}});
  s = CheckContoursDoNotCross({bow});
  EXPECT_NE(s.message().find("bow (level 100) crosses itself at (50, 50)"), std::string::npos)
      << s.message();
  // A closed ring is not a self-crossing.
  EXPECT_TRUE(CheckContoursDoNotCross({Line("ring", 5, Circle(0, 0, 10, 12))}).ok());
  // BuildContourTin refuses what the check refuses.
  EXPECT_FALSE(BuildContourTin({a, b}).ok());
}

TEST(ContourDem, RejectsBadInput) {
  EXPECT_EQ(BuildContourTin({}).status().code(), StatusCode::kInvalidArgument);
  EXPECT_FALSE(BuildContourTin({Line("one point", 1, {{0, 0}})}).ok());
  EXPECT_FALSE(BuildContourTin({Line("flat", 1, {{0, 0}, {1, 1}, {2, 2}})}).ok());
  const auto ok = Line("x", 1, {{0, 0}, {10, 0}, {5, 7}});
  EXPECT_FALSE(DemFromContours({ok}, 0).ok());
  EXPECT_FALSE(DemFromContours({ok}, -1).ok());
  EXPECT_FALSE(DemFromContours({ok}, 1e-9).ok());  // too many cells
}

TEST(ContourDem, VinschgauRoundTripThroughGdalContours) {
  testing::TempDir dir;
  const std::string source = DataPath("dem/elev_vinschgau.tif");
  const std::string contours = dir.Path("contours.gpkg");
  ASSERT_TRUE(testing::MakeContours(source, contours, 50).ok());
  auto features = ReadLineFeatures(contours, {});
  ASSERT_TRUE(features.ok()) << features.status().ToString();
  std::vector<ContourLine> lines;
  for (const LineFeature& f : *features) {
    for (const auto& part : f.lines)
      lines.push_back({f.label, f.attributes["ELEV"].get<double>(), part});
  }
  auto original = testing::ReadGridWithGdal(source);
  ASSERT_TRUE(original.ok());

  ContourDemReport report;
  auto tin = BuildContourTin(lines, &report);
  ASSERT_TRUE(tin.ok()) << tin.status().ToString();
  ExpectValidContourTin(*tin);
  EXPECT_GT(report.flat_triangles_found, 1000);  // alpine ridges and valleys make many

  auto grid = DemFromContours(lines, original->geometry.cell_x, &report);
  ASSERT_TRUE(grid.ok()) << grid.status().ToString();
  double sum_sq = 0, max_diff = 0;
  int64_t compared = 0;
  for (int64_t r = 0; r < grid->geometry.height; ++r) {
    for (int64_t c = 0; c < grid->geometry.width; ++c) {
      if (!grid->IsValid(c, r)) continue;
      const double want =
          original->SampleBilinear(grid->geometry.CellCenterX(c), grid->geometry.CellCenterY(r));
      if (std::isnan(want)) continue;
      const double d = grid->At(c, r) - want;
      sum_sq += d * d;
      max_diff = std::max(max_diff, std::fabs(d));
      ++compared;
    }
  }
  const double rms = std::sqrt(sum_sq / static_cast<double>(compared));
  std::cout << "Vinschgau from 50 m contours: " << compared << " cells, RMS " << rms << " m, max "
            << max_diff << " m, " << report.steiner_points << " Steiner points in " << report.rounds
            << " rounds\n";
  EXPECT_GT(compared, 35000);
  // Bounds: the RMS stays below a quarter of the 50 m interval and no cell is off by two
  // intervals (the contours pin the surface to within one interval wherever they are dense).
  EXPECT_LT(rms, 12.5);
  EXPECT_LT(max_diff, 100.0);
}

}  // namespace
}  // namespace tinbase
