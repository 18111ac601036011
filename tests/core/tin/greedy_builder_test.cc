// Greedy insertion against an independent evaluator, on generated terrains and real DEMs.
#include "core/tin/greedy_builder.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include "core/tin/split_refinement.h"
#include "core/tin/tin_raster.h"
#include "tests/support/lattice_tin_checks.h"
#include "tests/support/read_grid.h"
#include "tests/support/terrain_grids.h"
#include "tests/support/test_support.h"
#include "tests/support/thread_count.h"
#include "tests/support/tin_checks.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::FitToDem;
using testing::HiddenTriangles;
using testing::MakeGrid;
using testing::Sines;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Everything a valid greedy result promises, checked independently of the builder.
void ExpectValidGreedyTin(const Tin& tin, const Grid& dem, double tolerance,
                          const GreedyReport& report) {
  SCOPED_TRACE("tolerance " + std::to_string(tolerance));
  ASSERT_GE(tin.vertices.size(), 4u);
  testing::ExpectCounterClockwise(tin);
  testing::ExpectNeighboursConsistent(tin);
  testing::ExpectLocallyDelaunay(tin);
  EXPECT_TRUE(tin.constraints.empty());
  // Every vertex is a cell centre with the cell's value (or a nodata corner's substitute).
  const GridGeometry& g = dem.geometry;
  for (const TinVertex& v : tin.vertices) {
    EXPECT_EQ(v.kind, VertexKind::kDem);
    const int64_t c = std::llround(g.ColumnAt(v.x));
    const int64_t r = std::llround(g.RowAt(v.y));
    ASSERT_TRUE(c >= 0 && c < g.width && r >= 0 && r < g.height);
    EXPECT_EQ(v.x, g.CellCenterX(c));
    EXPECT_EQ(v.y, g.CellCenterY(r));
    if (dem.IsValid(c, r)) {
      EXPECT_EQ(v.z, dem.At(c, r));
    }
  }
  // The triangles tile the grid's hull of cell centres: two per cell of the centre lattice.
  const double hull_area = std::fabs(g.cell_x * (g.width - 1) * g.cell_y * (g.height - 1));
  double area = 0;
  for (const TinTriangle& t : tin.triangles) {
    const TinVertex& a = tin.vertices[t.v[0]];
    const TinVertex& b = tin.vertices[t.v[1]];
    const TinVertex& c = tin.vertices[t.v[2]];
    area += 0.5 * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
  }
  EXPECT_NEAR(area, hull_area, 1e-9 * hull_area);
  // A triangle is visible exactly when its centroid's cell holds data.
  for (const TinTriangle& t : tin.triangles) {
    double x = 0, y = 0;
    for (uint32_t v : t.v) x += tin.vertices[v].x / 3, y += tin.vertices[v].y / 3;
    const int64_t c = std::llround(g.ColumnAt(x));
    const int64_t r = std::llround(g.RowAt(y));
    EXPECT_EQ(t.visible, dem.IsValid(c, r));
  }
  const testing::DemFit fit = FitToDem(tin, dem);
  EXPECT_EQ(fit.uncovered_cells, 0);
  EXPECT_LE(fit.max_error, tolerance + 1e-6);
  EXPECT_NEAR(report.max_error, fit.max_error, 1e-6);
  EXPECT_LE(report.rms_error, report.max_error);
  EXPECT_EQ(report.points, static_cast<int64_t>(tin.vertices.size()));
}

TEST(GreedyBuilderTest, PlaneNeedsOnlyTheCorners) {
  const Grid dem = MakeGrid(120, 80, [](double x, double y) { return 100 + 0.3 * x - 0.2 * y; });
  GreedyReport report;
  auto tin = BuildGreedyTin(dem, {.tolerance = 0.01}, &report);
  ASSERT_TRUE(tin.ok()) << tin.status().ToString();
  EXPECT_EQ(tin->vertices.size(), 4u);
  EXPECT_EQ(tin->triangles.size(), 2u);
  ExpectValidGreedyTin(*tin, dem, 0.01, report);
  EXPECT_LT(report.max_error, 1e-3);
}

TEST(GreedyBuilderTest, ConeGetsItsApex) {
  // Apex at the centre of cell (50, 40).
  const Grid dem = MakeGrid(
      101, 81, [](double x, double y) { return 800 - 0.8 * std::hypot(x - 505.0, y + 405.0); });
  GreedyReport report;
  auto tin = BuildGreedyTin(dem, {.tolerance = 2}, &report);
  ASSERT_TRUE(tin.ok()) << tin.status().ToString();
  ExpectValidGreedyTin(*tin, dem, 2, report);
  bool apex = false;
  for (const TinVertex& v : tin->vertices) apex |= (v.x == 500505.0 && v.y == 5199595.0);
  EXPECT_TRUE(apex) << "the apex is the worst sample of the corner triangulation";
}

TEST(GreedyBuilderTest, SinesWithinEachTolerance) {
  const Grid dem = MakeGrid(300, 240, Sines);
  int64_t previous_points = 0;
  for (double tolerance : {20.0, 5.0, 1.0}) {
    GreedyReport report;
    auto tin = BuildGreedyTin(dem, {.tolerance = tolerance}, &report);
    ASSERT_TRUE(tin.ok()) << tin.status().ToString();
    ExpectValidGreedyTin(*tin, dem, tolerance, report);
    EXPECT_GT(report.points, previous_points) << "a finer tolerance needs more points";
    previous_points = report.points;
  }
}

TEST(GreedyBuilderTest, RandomTerrainsReproducibleBySeed) {
  const unsigned seed = std::random_device{}();
  std::printf("RandomTerrainsReproducibleBySeed seed %u\n", seed);
  std::mt19937 rng(seed);
  for (int round = 0; round < 8; ++round) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " round " + std::to_string(round));
    const Grid dem = testing::RandomTerrain(rng, 90, /*hole_chance=*/0);
    const double tolerance = 0.5 + 10 * std::uniform_real_distribution<double>()(rng);
    GreedyReport report;
    auto tin = BuildGreedyTin(dem, {.tolerance = tolerance}, &report);
    ASSERT_TRUE(tin.ok()) << tin.status().ToString();
    ExpectValidGreedyTin(*tin, dem, tolerance, report);
  }
}

// Tiled passes (for streamed DEMs) keep every promise of the strict order, with a point count
// close to it; nodata holes and tiles that do not divide the grid included.
TEST(GreedyBuilderTest, TiledPassesKeepTheBoundWithFewExtraPoints) {
  Grid dem = MakeGrid(517, 389, Sines);
  for (int64_t r = 100; r < 160; ++r)
    for (int64_t c = 200; c < 290; ++c) dem.cells[static_cast<size_t>(r * 517 + c)] = kNaN;
  for (double tolerance : {10.0, 1.0}) {
    GreedyReport strict, tiled;
    auto a = BuildGreedyTin(dem, {.tolerance = tolerance}, &strict);
    auto b = BuildGreedyTin(dem, {.tolerance = tolerance, .tile = 64}, &tiled);
    ASSERT_TRUE(a.ok() && b.ok());
    ExpectValidGreedyTin(*b, dem, tolerance, tiled);
    EXPECT_GE(tiled.points, strict.points * 95 / 100) << tolerance;
    EXPECT_LE(tiled.points, strict.points * 115 / 100) << tolerance;
  }
}

// A split build (core/tin/split_refinement.h) keeps every promise of an unsplit one, each checked
// against every cell, with about as many points: nodata holes and a nodata corner, a south-up
// grid, and a grid taller than wide (split across its rows).
TEST(GreedyBuilderTest, SplitKeepsTheBoundCellByCell) {
  Grid holes = MakeGrid(517, 389, [](double x, double y) {
    if (std::hypot(x - 2600.0, y + 1900.0) < 400 || x + (-y) < 150) return kNaN;
    return Sines(x, y);
  });
  Grid south_up = MakeGrid(300, 200, Sines);
  south_up.geometry.cell_y = 10;
  Grid tall = MakeGrid(150, 420, Sines);
  for (const Grid* dem : {&holes, &south_up, &tall}) {
    for (double tolerance : {10.0, 1.0}) {
      SCOPED_TRACE(std::to_string(dem->geometry.width) + " x " +
                   std::to_string(dem->geometry.height));
      GreedyReport one, two;
      auto a = BuildGreedyTin(*dem, {.tolerance = tolerance, .split = GreedySplit::kNever}, &one);
      auto b = BuildGreedyTin(*dem, {.tolerance = tolerance, .split = GreedySplit::kAlways}, &two);
      ASSERT_TRUE(a.ok() && b.ok());
      ExpectValidGreedyTin(*b, *dem, tolerance, two);
      // The bound is reached, so the cell-by-cell check above works at its edge.
      EXPECT_GT(two.max_error, 0.9 * tolerance);
      // Greedy insertion is not optimal: another insertion order (each half its own) may need a
      // few per cent fewer points (95 % here on the tall grid at 1 m), never many more.
      EXPECT_GE(two.points, one.points * 90 / 100);
      EXPECT_LE(two.points, one.points * 103 / 100 + 4);  // + the seam's ends
    }
  }
}

// The narrowest grids a split allows (3 cells across, 2 along the seam) and random sizes.
TEST(GreedyBuilderTest, SplitOnRandomTerrains) {
  const unsigned seed = std::random_device{}();
  std::printf("SplitOnRandomTerrains seed %u\n", seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int round = 0; round < 12; ++round) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " round " + std::to_string(round));
    const int64_t width = round == 0 ? 3 : 2 + static_cast<int64_t>(rng() % 120);
    const int64_t height = round == 0 ? 2 : 2 + static_cast<int64_t>(rng() % 120);
    const double a = 200 * unit(rng), fx = 20 + 300 * unit(rng), fy = 20 + 300 * unit(rng);
    const double noise = 5 * unit(rng);
    std::mt19937 cell_rng(rng());
    const Grid dem = MakeGrid(width, height, [&](double x, double y) {
      return a * std::sin(x / fx) * std::cos(y / fy) + noise * unit(cell_rng);
    });
    const double tolerance = 0.5 + 10 * unit(rng);
    GreedyReport report;
    auto tin =
        BuildGreedyTin(dem, {.tolerance = tolerance, .split = GreedySplit::kAlways}, &report);
    ASSERT_TRUE(tin.ok()) << tin.status().ToString();
    ExpectValidGreedyTin(*tin, dem, tolerance, report);
  }
}

// An automatic build splits only when the seam's chain is long (core/tin/split_refinement.h): a
// coarse tolerance, whose chain is short, gives exactly the unsplit TIN, a fine one exactly the
// split TIN.
TEST(GreedyBuilderTest, AutomaticSplitOnlyOnALongSeam) {
  const Grid dem = MakeGrid(400, 300, Sines);
  ASSERT_TRUE(WorthSplitting(dem.geometry));
  const BoundaryElevationFn z = [&](int64_t c, int64_t r) { return double{dem.At(c, r)}; };
  const auto same = [](const Tin& a, const Tin& b) {
    if (a.vertices.size() != b.vertices.size() || a.triangles.size() != b.triangles.size())
      return false;
    for (size_t i = 0; i < a.vertices.size(); ++i) {
      if (a.vertices[i].x != b.vertices[i].x || a.vertices[i].y != b.vertices[i].y) return false;
    }
    return true;
  };
  for (const double tolerance : {100.0, 0.5}) {
    SCOPED_TRACE("tolerance " + std::to_string(tolerance));
    const bool long_seam =
        ChooseSeam(dem, tolerance, z).chain_vertices >= MinSeamVertices(dem.geometry);
    EXPECT_EQ(long_seam, tolerance < 1);  // the premise: one case of each
    auto automatic = BuildGreedyTin(dem, {.tolerance = tolerance});
    auto one = BuildGreedyTin(dem, {.tolerance = tolerance, .split = GreedySplit::kNever});
    auto two = BuildGreedyTin(dem, {.tolerance = tolerance, .split = GreedySplit::kAlways});
    ASSERT_TRUE(automatic.ok() && one.ok() && two.ok());
    ASSERT_FALSE(same(*one, *two));  // else the comparison below tells nothing
    EXPECT_TRUE(same(*automatic, long_seam ? *two : *one));
  }
}

TEST(GreedyBuilderTest, MaxPointsHonoured) {
  const Grid dem = MakeGrid(200, 150, Sines);
  for (int64_t max_points : {4, 5, 37, 200}) {
    GreedyReport report;
    auto tin = BuildGreedyTin(dem, {.tolerance = 0.1, .max_points = max_points}, &report);
    ASSERT_TRUE(tin.ok()) << tin.status().ToString();
    EXPECT_EQ(static_cast<int64_t>(tin->vertices.size()), max_points);
    EXPECT_GT(report.max_error, 0.1) << "stopped by the budget, not the tolerance";
    testing::ExpectCounterClockwise(*tin);
    testing::ExpectLocallyDelaunay(*tin);
    EXPECT_NEAR(report.max_error, FitToDem(*tin, dem).max_error, 1e-6);
  }
}

// The report's errors are measured over every valid cell: on one thread, on two (rows split at
// a word of the cell bitmap, here row 128 of a 157-cell-wide grid) and over a streamed source,
// the same TIN gives the same figures, which match an independent measure (tin_raster.h).
TEST(GreedyBuilderTest, ReportMeasuresEveryValidCellOnOneOrTwoThreads) {
  const Grid dem = MakeGrid(157, 200, [](double x, double y) {
    return std::hypot(x - 700.0, y + 900.0) < 200 ? kNaN : Sines(x, y);
  });
  // A point budget keeps the build unsplit, so the streamed run makes the same TIN.
  const GreedyOptions options{.tolerance = 0.5, .max_points = 1500};
  GreedyReport on_one, on_two, streamed;
  auto tin = testing::WithThreads(1, [&] { return BuildGreedyTin(dem, options, &on_one); });
  ASSERT_TRUE(tin.ok()) << tin.status().ToString();
  ASSERT_TRUE(testing::WithThreads(2, [&] { return BuildGreedyTin(dem, options, &on_two); }).ok());
  GridCellSource source(dem);
  ASSERT_TRUE(BuildGreedyTin(source, options, &streamed).ok());
  const TinGridError want = CompareTinToGrid(*tin, dem);
  ASSERT_EQ(want.uncovered, 0);
  ASSERT_GT(want.rms_error, 0);
  for (const GreedyReport* report : {&on_one, &on_two, &streamed}) {
    EXPECT_NEAR(report->max_error, want.max_error, 1e-6);
    EXPECT_NEAR(report->rms_error, want.rms_error, 1e-9 * want.rms_error + 1e-9);
    EXPECT_EQ(report->points, 1500);
  }
  EXPECT_EQ(on_two.max_error, on_one.max_error);
}

TEST(GreedyBuilderTest, TinyToleranceTakesEveryCell) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> noise(0, 50);
  const Grid dem = MakeGrid(23, 17, [&](double, double) { return 1000 + noise(rng); });
  GreedyReport report;
  auto tin = BuildGreedyTin(dem, {.tolerance = 1e-12}, &report);
  ASSERT_TRUE(tin.ok()) << tin.status().ToString();
  EXPECT_EQ(tin->vertices.size(), 23u * 17u);
  ExpectValidGreedyTin(*tin, dem, 1e-12, report);
}

TEST(GreedyBuilderTest, RejectsBadInput) {
  const Grid dem = MakeGrid(10, 10, Sines);
  for (double tolerance : {0.0, -1.0, kNaN}) {
    auto tin = BuildGreedyTin(dem, {.tolerance = tolerance});
    ASSERT_FALSE(tin.ok());
    EXPECT_EQ(tin.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(tin.status().message().find("tolerance"), std::string::npos)
        << tin.status().message();
  }
  for (int64_t max_points : {-1, 1, 3}) {
    auto tin = BuildGreedyTin(dem, {.tolerance = 1, .max_points = max_points});
    ASSERT_FALSE(tin.ok());
    EXPECT_NE(tin.status().message().find("max_points"), std::string::npos);
  }

  auto empty = BuildGreedyTin(Grid{}, {.tolerance = 1});
  ASSERT_FALSE(empty.ok());
  EXPECT_EQ(empty.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(empty.status().message().find("empty"), std::string::npos);

  auto line = BuildGreedyTin(MakeGrid(1, 50, Sines), {.tolerance = 1});
  ASSERT_FALSE(line.ok());
  EXPECT_NE(line.status().message().find("2 x 2"), std::string::npos);

  Grid nodata = MakeGrid(20, 20, [](double, double) { return kNaN; });
  auto all_nan = BuildGreedyTin(nodata, {.tolerance = 1});
  ASSERT_FALSE(all_nan.ok());
  EXPECT_EQ(all_nan.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(all_nan.status().message().find("no valid cell"), std::string::npos);
}

TEST(GreedyBuilderTest, NodataHolesAndCorners) {
  // A nodata disc in the middle and a nodata band along the top-left corner.
  const Grid dem = MakeGrid(160, 120, [](double x, double y) {
    if (std::hypot(x - 800.0, y + 600.0) < 250) return kNaN;
    if (x + (-y) < 120) return kNaN;
    return Sines(x, y);
  });
  ASSERT_FALSE(dem.IsValid(0, 0));
  for (double tolerance : {5.0, 1.0}) {
    GreedyReport report;
    auto tin = BuildGreedyTin(dem, {.tolerance = tolerance}, &report);
    ASSERT_TRUE(tin.ok()) << tin.status().ToString();
    ExpectValidGreedyTin(*tin, dem, tolerance, report);
    // The nodata corner takes the mean of the nearest valid cells: the first square window
    // around (0, 0) with any valid cell.
    const TinVertex& corner = tin->vertices[0];
    ASSERT_EQ(corner.x, dem.geometry.CellCenterX(0));
    ASSERT_EQ(corner.y, dem.geometry.CellCenterY(0));
    EXPECT_NEAR(corner.z, testing::FirstValidWindowMean(dem), 1e-9);
    EXPECT_GT(HiddenTriangles(*tin), 0);
  }
}

TEST(GreedyBuilderTest, SouthUpGrid) {
  Grid dem = MakeGrid(90, 70, Sines);
  dem.geometry.cell_y = 10;  // rows run northwards
  GreedyReport report;
  auto tin = BuildGreedyTin(dem, {.tolerance = 2}, &report);
  ASSERT_TRUE(tin.ok()) << tin.status().ToString();
  ExpectValidGreedyTin(*tin, dem, 2, report);
}

// Returns the number of hidden triangles of the last build.
int CheckRealDem(const std::string& relative, std::initializer_list<double> tolerances,
                 GreedySplit split = GreedySplit::kAutomatic) {
  auto dem = testing::ReadGridWithGdal(DataPath(relative));
  EXPECT_TRUE(dem.ok()) << dem.status().ToString();
  if (!dem.ok()) return -1;
  int hidden = -1;
  for (double tolerance : tolerances) {
    GreedyReport report;
    const auto start = std::chrono::steady_clock::now();
    auto tin = BuildGreedyTin(*dem, {.tolerance = tolerance, .split = split}, &report);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_TRUE(tin.ok()) << tin.status().ToString();
    if (!tin.ok()) return -1;
    std::printf(
        "%s at %.0f m, split %d: %lld points, %zu triangles, max %.3f m, rms %.3f m, "
        "%.2f s\n",
        relative.c_str(), tolerance, static_cast<int>(split), static_cast<long long>(report.points),
        tin->triangles.size(), report.max_error, report.rms_error, seconds);
    ExpectValidGreedyTin(*tin, *dem, tolerance, report);
    hidden = HiddenTriangles(*tin);
  }
  return hidden;
}

// The same TIN and report, bit for bit, on 1, 2 and 4 threads: split builds (automatic and
// forced), an unsplit one whose largest scans are shared, and one over a streamed source.
TEST(GreedyBuilderTest, SameTinOnAnyNumberOfThreads) {
  const Grid dem = MakeGrid(700, 520, [](double x, double y) {
    return std::hypot(x - 2600.0, y + 1900.0) < 300 ? kNaN : Sines(x, y);
  });
  ASSERT_TRUE(WorthSplitting(dem.geometry));
  for (const GreedyOptions& options :
       {GreedyOptions{.tolerance = 0.5}, GreedyOptions{.tolerance = 5.0},
        GreedyOptions{.tolerance = 2.0, .split = GreedySplit::kAlways},
        GreedyOptions{.tolerance = 2.0, .split = GreedySplit::kNever},
        GreedyOptions{.tolerance = 40.0, .split = GreedySplit::kNever}}) {
    SCOPED_TRACE("tolerance " + std::to_string(options.tolerance) + ", split " +
                 std::to_string(static_cast<int>(options.split)));
    const auto build = [&](int threads) {
      GreedyReport report;
      auto tin =
          testing::WithThreads(threads, [&] { return BuildGreedyTin(dem, options, &report); });
      EXPECT_TRUE(tin.ok()) << tin.status().ToString();
      return std::pair{tin.ok() ? *tin : Tin(), report};
    };
    const auto [want, want_report] = build(1);
    ASSERT_GT(want.triangles.size(), 100u);
    for (int threads : testing::kThreadCounts) {
      SCOPED_TRACE(std::to_string(threads) + " threads");
      const auto [got, report] = build(threads);
      testing::ExpectSameTin(got, want);
      EXPECT_EQ(report.max_error, want_report.max_error);
      EXPECT_EQ(report.rms_error, want_report.rms_error);
      EXPECT_EQ(report.points, want_report.points);
    }
  }
  GridCellSource source(dem);
  const auto streamed = [&](int threads) {
    return testing::WithThreads(threads, [&] { return BuildGreedyTin(source, {.tolerance = 2}); });
  };
  const auto want = streamed(1);
  ASSERT_TRUE(want.ok());
  for (int threads : testing::kThreadCounts) {
    const auto got = streamed(threads);
    ASSERT_TRUE(got.ok());
    testing::ExpectSameTin(*got, *want);
  }
}

TEST(GreedyBuilderTest, VinschgauDem) { CheckRealDem("dem/elev_vinschgau.tif", {20.0, 5.0, 1.0}); }

// Nodata outside Luxembourg: real holes and nodata corners.
TEST(GreedyBuilderTest, LuxembourgDemWithNodata) {
  for (GreedySplit split : {GreedySplit::kNever, GreedySplit::kAlways})
    EXPECT_GT(CheckRealDem("dem/elev.tif", {20.0, 5.0, 1.0}, split), 0);
}

TEST(GreedyBuilderTest, SrtmN43E007) {
  for (GreedySplit split : {GreedySplit::kNever, GreedySplit::kAlways})
    CheckRealDem("dem/N43E007.hgt", {20.0, 5.0, 1.0}, split);
}

}  // namespace
}  // namespace tinbase
