// The very-important-point builder against an independent significance and an independent
// evaluator, on generated terrains and real DEMs.
#include "core/tin/vip_builder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <utility>

#include "tests/support/lattice_tin_checks.h"
#include "tests/support/read_grid.h"
#include "tests/support/terrain_grids.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_checks.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::FitToDem;
using testing::MakeGrid;
using testing::Sines;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// The header's definition, written out case by case: the mean vertical distance from the cell
// to the lines through its opposite neighbour pairs that exist and hold data.
double ExpectedSignificance(const Grid& dem, int64_t c, int64_t r) {
  const int64_t w = dem.geometry.width, h = dem.geometry.height;
  const bool vertical_border = c == 0 || c == w - 1;
  const bool horizontal_border = r == 0 || r == h - 1;
  if (vertical_border && horizontal_border) return kInf;
  if (!dem.IsValid(c, r)) return kNaN;
  std::vector<std::pair<std::pair<int64_t, int64_t>, std::pair<int64_t, int64_t>>> pairs;
  if (vertical_border) {
    pairs = {{{c, r - 1}, {c, r + 1}}};
  } else if (horizontal_border) {
    pairs = {{{c - 1, r}, {c + 1, r}}};
  } else {
    pairs = {{{c, r - 1}, {c, r + 1}},
             {{c - 1, r}, {c + 1, r}},
             {{c - 1, r - 1}, {c + 1, r + 1}},
             {{c + 1, r - 1}, {c - 1, r + 1}}};
  }
  double sum = 0;
  int n = 0;
  for (const auto& [p, q] : pairs) {
    if (!dem.IsValid(p.first, p.second) || !dem.IsValid(q.first, q.second)) continue;
    const double line_z = (dem.At(p.first, p.second) + double{dem.At(q.first, q.second)}) / 2;
    sum += std::fabs(dem.At(c, r) - line_z);
    ++n;
  }
  return n == 0 ? kInf : sum / n;
}

std::set<std::pair<int64_t, int64_t>> VertexCells(const Tin& tin, const Grid& dem) {
  std::set<std::pair<int64_t, int64_t>> cells;
  for (const TinVertex& v : tin.vertices) {
    const auto p = testing::LatticeOf(dem.geometry, v);
    cells.insert({p.col, p.row});
  }
  return cells;
}

// Everything a VIP result promises, checked independently of the builder.
void ExpectValidVip(const Tin& tin, const Grid& dem, const VipReport& report) {
  ASSERT_GE(tin.vertices.size(), 4u);
  testing::ExpectCounterClockwise(tin);
  testing::ExpectNeighboursConsistent(tin);
  testing::ExpectLocallyDelaunay(tin);
  testing::ExpectEulerDisc(tin);
  testing::ExpectVerticesOnCells(tin, dem);
  testing::ExpectTilesGridWithoutTJunctions(tin, dem);
  testing::ExpectNodataHidden(tin, dem);
  EXPECT_TRUE(tin.constraints.empty());
  const testing::DemFit fit = FitToDem(tin, dem);
  EXPECT_EQ(fit.uncovered_cells, 0);
  EXPECT_NEAR(report.max_error, fit.max_error, 1e-6);
  EXPECT_LE(report.rms_error, report.max_error);
  EXPECT_EQ(report.points, static_cast<int64_t>(tin.vertices.size()));
}

// The kept cells are exactly the corners and the cells whose independently computed
// significance reaches the threshold.
void ExpectSelectionMatches(const Tin& tin, const Grid& dem, double threshold) {
  const auto kept = VertexCells(tin, dem);
  int64_t mismatches = 0;
  for (int64_t r = 0; r < dem.geometry.height; ++r) {
    for (int64_t c = 0; c < dem.geometry.width; ++c) {
      const double s = ExpectedSignificance(dem, c, r);
      const bool expected = s >= threshold;  // false for NaN
      if (expected != (kept.count({c, r}) > 0) && ++mismatches <= 5) {
        ADD_FAILURE() << "cell (" << c << ", " << r << ") significance " << s << " threshold "
                      << threshold << (expected ? " missing" : " kept");
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
}

VipReport BuildAndCheck(const Grid& dem, const VipOptions& options, Tin* out = nullptr) {
  SCOPED_TRACE("threshold " + std::to_string(options.threshold));
  VipReport report;
  auto tin = BuildVipTin(dem, options, &report);
  EXPECT_TRUE(tin.ok()) << tin.status().ToString();
  if (!tin.ok()) return report;
  ExpectValidVip(*tin, dem, report);
  if (options.max_points == 0) ExpectSelectionMatches(*tin, dem, options.threshold);
  if (out != nullptr) *out = std::move(tin).value();
  return report;
}

TEST(VipBuilderTest, PlaneKeepsOnlyTheCorners) {
  const Grid dem = MakeGrid(120, 80, [](double x, double y) { return 100 + 0.3 * x - 0.2 * y; });
  const VipReport report = BuildAndCheck(dem, {.threshold = 0.01});
  EXPECT_EQ(report.points, 4);
  EXPECT_EQ(report.significant_cells, 4);
  EXPECT_LT(report.max_error, 1e-3);
}

TEST(VipBuilderTest, SignificanceIsTheMeanVerticalDistanceToTheFourLines) {
  // A 3 x 3 block: the centre is 10 above the N-S and E-W lines' midpoints (0), 10 - 3 above
  // the NW-SE one ((2 + 4) / 2) and 10 - 1 above the NE-SW one ((0 + 2) / 2).
  Grid dem = MakeGrid(3, 3, [](double, double) { return 0.0; });
  dem.cells = {2, 0,  0,  //
               0, 10, 0,  //
               2, 0,  4};
  EXPECT_DOUBLE_EQ(VipSignificance(dem, 1, 1), (10 + 10 + 7 + 9) / 4.0);
  // The border cell (1, 0) has one line, along the top row: |0 - (2 + 0) / 2|.
  EXPECT_DOUBLE_EQ(VipSignificance(dem, 1, 0), 1.0);
  EXPECT_EQ(VipSignificance(dem, 0, 0), kInf);
  dem.cells[0] = kNaN;  // the NW-SE line loses an end
  EXPECT_DOUBLE_EQ(VipSignificance(dem, 1, 1), (10 + 10 + 9) / 3.0);
  EXPECT_EQ(VipSignificance(dem, 1, 0), kInf) << "a data edge along the border is kept";
}

TEST(VipBuilderTest, ConeKeepsItsApex) {
  const Grid dem = MakeGrid(
      101, 81, [](double x, double y) { return 800 - 0.8 * std::hypot(x - 505.0, y + 405.0); });
  Tin tin;
  BuildAndCheck(dem, {.threshold = 2}, &tin);
  EXPECT_TRUE(VertexCells(tin, dem).count({50, 40}));
}

TEST(VipBuilderTest, PointsFallAsTheThresholdRises) {
  const Grid dem = MakeGrid(300, 240, Sines);
  int64_t previous = std::numeric_limits<int64_t>::max();
  for (double threshold : {0.0, 0.05, 0.2, 0.5, 2.0}) {
    const VipReport report = BuildAndCheck(dem, {.threshold = threshold});
    EXPECT_LT(report.points, previous);
    previous = report.points;
    if (threshold == 0) {
      EXPECT_EQ(report.points, 300 * 240) << "threshold 0 keeps every cell";
      EXPECT_LT(report.max_error, 1e-9);
    }
  }
}

TEST(VipBuilderTest, MaxPointsKeepsTheMostSignificant) {
  const Grid dem = MakeGrid(200, 150, Sines);
  for (int64_t max_points : {4, 5, 37, 500}) {
    SCOPED_TRACE("max_points " + std::to_string(max_points));
    VipReport report;
    auto tin = BuildVipTin(dem, {.threshold = 0.1, .max_points = max_points}, &report);
    ASSERT_TRUE(tin.ok()) << tin.status().ToString();
    EXPECT_EQ(static_cast<int64_t>(tin->vertices.size()), max_points);
    EXPECT_GT(report.significant_cells, max_points);
    ExpectValidVip(*tin, dem, report);
    const auto kept = VertexCells(*tin, dem);
    double weakest_kept = kInf, strongest_dropped = 0;
    for (int64_t r = 0; r < dem.geometry.height; ++r) {
      for (int64_t c = 0; c < dem.geometry.width; ++c) {
        const double s = ExpectedSignificance(dem, c, r);
        if (kept.count({c, r})) {
          weakest_kept = std::min(weakest_kept, s);
        } else {
          strongest_dropped = std::max(strongest_dropped, s);
        }
      }
    }
    EXPECT_GE(weakest_kept, strongest_dropped);
  }
}

TEST(VipBuilderTest, RandomTerrainsReproducibleBySeed) {
  const unsigned seed = std::random_device{}();
  std::printf("RandomTerrainsReproducibleBySeed seed %u\n", seed);
  std::mt19937 rng(seed);
  for (int round = 0; round < 10; ++round) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " round " + std::to_string(round));
    const Grid dem = testing::RandomTerrain(rng, 80, /*hole_chance=*/0.3);
    if (testing::AllNodata(dem)) continue;
    BuildAndCheck(dem, {.threshold = 3 * std::uniform_real_distribution<double>()(rng)});
  }
}

TEST(VipBuilderTest, NodataHolesAndCorners) {
  const Grid dem = MakeGrid(160, 120, [](double x, double y) {
    if (std::hypot(x - 800.0, y + 600.0) < 250) return kNaN;
    if (x + (-y) < 120) return kNaN;
    return Sines(x, y);
  });
  ASSERT_FALSE(dem.IsValid(0, 0));
  Tin tin;
  BuildAndCheck(dem, {.threshold = 1}, &tin);
  EXPECT_GT(testing::HiddenTriangles(tin), 0);
  // Vertices are in row-major cell order, so the nodata corner (0, 0) comes first, with the
  // mean of the first square window around it that holds valid cells.
  const TinVertex& corner = tin.vertices[0];
  ASSERT_EQ(corner.x, dem.geometry.CellCenterX(0));
  ASSERT_EQ(corner.y, dem.geometry.CellCenterY(0));
  EXPECT_NEAR(corner.z, testing::FirstValidWindowMean(dem), 1e-9);
}

TEST(VipBuilderTest, SouthUpGrid) {
  Grid dem = MakeGrid(90, 70, Sines);
  dem.geometry.cell_y = 10;  // rows run northwards
  BuildAndCheck(dem, {.threshold = 0.5});
}

TEST(VipBuilderTest, RejectsBadInput) {
  const Grid dem = MakeGrid(10, 10, Sines);
  for (double threshold : {-1.0, kNaN, kInf}) {
    auto tin = BuildVipTin(dem, {.threshold = threshold});
    ASSERT_FALSE(tin.ok());
    EXPECT_EQ(tin.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(tin.status().message().find("threshold"), std::string::npos)
        << tin.status().message();
  }
  for (int64_t max_points : {-1, 1, 3}) {
    auto tin = BuildVipTin(dem, {.threshold = 1, .max_points = max_points});
    ASSERT_FALSE(tin.ok());
    EXPECT_NE(tin.status().message().find("max_points"), std::string::npos);
  }
  auto empty = BuildVipTin(Grid{}, {});
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.status().message().find("empty"), std::string::npos);
  auto line = BuildVipTin(MakeGrid(50, 1, Sines), {});
  ASSERT_FALSE(line.ok());
  EXPECT_NE(line.status().message().find("2 x 2"), std::string::npos);
  auto all_nan = BuildVipTin(MakeGrid(20, 20, [](double, double) { return kNaN; }), {});
  ASSERT_FALSE(all_nan.ok());
  EXPECT_NE(all_nan.status().message().find("no valid cell"), std::string::npos);
}

void CheckRealDem(const std::string& relative, std::initializer_list<double> thresholds) {
  auto dem = testing::ReadGridWithGdal(DataPath(relative));
  ASSERT_TRUE(dem.ok()) << dem.status().ToString();
  int64_t previous = std::numeric_limits<int64_t>::max();
  for (double threshold : thresholds) {
    const auto start = std::chrono::steady_clock::now();
    Tin tin;
    const VipReport report = BuildAndCheck(*dem, {.threshold = threshold}, &tin);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf(
        "%s at threshold %.1f m: %lld points, %zu triangles, max %.3f m, rms %.3f m "
        "(build and checks %.2f s)\n",
        relative.c_str(), threshold, static_cast<long long>(report.points), tin.triangles.size(),
        report.max_error, report.rms_error, seconds);
    EXPECT_LT(report.points, previous);
    previous = report.points;
  }
}

TEST(VipBuilderTest, VinschgauDem) { CheckRealDem("dem/elev_vinschgau.tif", {5.0, 20.0, 50.0}); }

TEST(VipBuilderTest, LuxembourgDemWithNodata) { CheckRealDem("dem/elev.tif", {1.0, 5.0}); }

TEST(VipBuilderTest, SrtmN43E007) { CheckRealDem("dem/N43E007.hgt", {5.0, 10.0, 20.0}); }

}  // namespace
}  // namespace tinbase
