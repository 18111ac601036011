// The binary triangle tree (RTIN) builder against an independent evaluator: the true error over
// every valid cell within the tolerance, a crack- and T-junction-free tiling of the grid, on
// generated terrains and real DEMs; and paper 000's Table 1 on a real 300 x 300 window.
#include "core/tin/rtin_builder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
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

// Every triangle is right-isosceles in cell space (a binary-tree triangle): two equal legs and a
// hypotenuse of twice their squared length.
void ExpectRightIsosceles(const Tin& tin, const Grid& dem) {
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    std::array<int64_t, 3> sq{};
    for (int i = 0; i < 3; ++i) {
      const auto p = testing::LatticeOf(dem.geometry, tin.vertices[tin.triangles[t].v[i]]);
      const auto q =
          testing::LatticeOf(dem.geometry, tin.vertices[tin.triangles[t].v[(i + 1) % 3]]);
      sq[i] = (p.col - q.col) * (p.col - q.col) + (p.row - q.row) * (p.row - q.row);
    }
    std::sort(sq.begin(), sq.end());
    EXPECT_TRUE(sq[0] == sq[1] && sq[2] == 2 * sq[0]) << "triangle " << t;
  }
}

// Everything an RTIN promises, checked independently of the builder.
void ExpectValidRtin(const Tin& tin, const Grid& dem, double tolerance, const RtinReport& report) {
  SCOPED_TRACE("tolerance " + std::to_string(tolerance));
  ASSERT_GE(tin.triangles.size(), 2u);
  testing::ExpectCounterClockwise(tin);
  testing::ExpectNeighboursConsistent(tin);
  testing::ExpectEulerDisc(tin);
  testing::ExpectVerticesOnCells(tin, dem);
  testing::ExpectTilesGridWithoutTJunctions(tin, dem);
  testing::ExpectNodataHidden(tin, dem);
  ExpectRightIsosceles(tin, dem);
  EXPECT_TRUE(tin.constraints.empty());
  const testing::DemFit fit = FitToDem(tin, dem);
  EXPECT_EQ(fit.uncovered_cells, 0);
  EXPECT_LE(fit.max_error, tolerance + 1e-6) << "the true error exceeds the tolerance";
  EXPECT_NEAR(report.max_error, fit.max_error, 1e-6);
  EXPECT_LE(report.rms_error, report.max_error);
  EXPECT_EQ(report.points, static_cast<int64_t>(tin.vertices.size()));
  EXPECT_EQ(report.triangles, static_cast<int64_t>(tin.triangles.size()));
}

RtinReport BuildAndCheck(const Grid& dem, double tolerance, Tin* out = nullptr) {
  RtinReport report;
  auto tin = BuildRtinTin(dem, {.tolerance = tolerance}, &report);
  EXPECT_TRUE(tin.ok()) << tin.status().ToString();
  if (!tin.ok()) return report;
  ExpectValidRtin(*tin, dem, tolerance, report);
  if (out != nullptr) *out = std::move(tin).value();
  return report;
}

TEST(RtinBuilderTest, PlaneOnAPowerOfTwoLatticeIsTwoTriangles) {
  const Grid dem = MakeGrid(129, 129, [](double x, double y) { return 100 + 0.3 * x - 0.2 * y; });
  const RtinReport report = BuildAndCheck(dem, 0.01);
  EXPECT_EQ(report.points, 4);
  EXPECT_EQ(report.triangles, 2);
  EXPECT_EQ(report.lattice_size, 129);
}

TEST(RtinBuilderTest, PlaneOnOtherSizesRefinesOnlyTowardsThePaddedEdges) {
  const auto plane = [](double x, double y) { return 100 + 0.3 * x - 0.2 * y; };
  // 97 - 1 = 96 = 3 * 32: straddling squares stop at size 32; 120 - 1 is odd: unit triangles.
  for (auto [w, h] : {std::pair{97, 65}, std::pair{120, 80}, std::pair{2, 2}, std::pair{3, 7}}) {
    SCOPED_TRACE(std::to_string(w) + " x " + std::to_string(h));
    const Grid dem = MakeGrid(w, h, plane);
    const RtinReport report = BuildAndCheck(dem, 0.01);
    EXPECT_LT(report.max_error, 1e-3);
  }
  // Padding costs nothing where the sides are 2^j * m + 1 with small m.
  const RtinReport tidy = BuildAndCheck(MakeGrid(97, 65, plane), 0.01);
  const RtinReport ragged = BuildAndCheck(MakeGrid(96, 64, plane), 0.01);
  EXPECT_LT(tidy.triangles, ragged.triangles);
}

TEST(RtinBuilderTest, SinesWithinEachToleranceAndCountsFallAsItRises) {
  const Grid dem = MakeGrid(300, 240, Sines);
  int64_t previous_triangles = std::numeric_limits<int64_t>::max();
  int64_t previous_points = std::numeric_limits<int64_t>::max();
  for (double tolerance : {0.0, 0.5, 1.0, 5.0, 20.0}) {
    const RtinReport report = BuildAndCheck(dem, tolerance);
    EXPECT_LT(report.triangles, previous_triangles);
    EXPECT_LT(report.points, previous_points);
    previous_triangles = report.triangles;
    previous_points = report.points;
  }
}

// A single-cell spike far from every coarse midpoint: only a bound over every covered cell (not
// the midpoint error of one level) catches it under a coarse triangle.
TEST(RtinBuilderTest, SpikeUnderACoarseTriangleIsResolved) {
  for (auto [col, row] : {std::pair{5, 3}, std::pair{61, 17}, std::pair{1, 1}, std::pair{63, 62}}) {
    SCOPED_TRACE("spike at " + std::to_string(col) + ", " + std::to_string(row));
    Grid dem = MakeGrid(65, 65, [](double, double) { return 50.0; });
    dem.cells[static_cast<size_t>(row) * 65 + col] = 57;
    Tin tin;
    BuildAndCheck(dem, 1.0, &tin);
    bool spike_is_vertex = false;
    for (const TinVertex& v : tin.vertices) spike_is_vertex |= v.z == 57;
    EXPECT_TRUE(spike_is_vertex);
  }
}

TEST(RtinBuilderTest, RandomTerrainsReproducibleBySeed) {
  const unsigned seed = std::random_device{}();
  std::printf("RandomTerrainsReproducibleBySeed seed %u\n", seed);
  std::mt19937 rng(seed);
  for (int round = 0; round < 12; ++round) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " round " + std::to_string(round));
    const Grid dem = testing::RandomTerrain(rng, 90, /*hole_chance=*/0.3);
    if (testing::AllNodata(dem)) continue;
    BuildAndCheck(dem, round % 4 == 0 ? 0.0 : 10 * std::uniform_real_distribution<double>()(rng));
  }
}

TEST(RtinBuilderTest, NodataHolesAndCorners) {
  const Grid dem = MakeGrid(160, 120, [](double x, double y) {
    if (std::hypot(x - 800.0, y + 600.0) < 250) return kNaN;
    if (x + (-y) < 120) return kNaN;
    return Sines(x, y);
  });
  ASSERT_FALSE(dem.IsValid(0, 0));
  for (double tolerance : {5.0, 1.0}) {
    Tin tin;
    BuildAndCheck(dem, tolerance, &tin);
    EXPECT_GT(testing::HiddenTriangles(tin), 0);
    // The nodata corner takes the mean of the first square window around it with valid cells.
    const TinVertex* corner = nullptr;
    for (const TinVertex& v : tin.vertices) {
      if (v.x == dem.geometry.CellCenterX(0) && v.y == dem.geometry.CellCenterY(0)) corner = &v;
    }
    ASSERT_NE(corner, nullptr);
    double expected = kNaN;
    for (int64_t radius = 1; std::isnan(expected); ++radius) {
      double sum = 0;
      int count = 0;
      for (int64_t r = 0; r <= radius; ++r) {
        for (int64_t c = 0; c <= radius; ++c) {
          if (dem.IsValid(c, r)) sum += dem.At(c, r), ++count;
        }
      }
      if (count > 0) expected = sum / count;
    }
    EXPECT_NEAR(corner->z, expected, 1e-9);
  }
}

TEST(RtinBuilderTest, SouthUpGrid) {
  Grid dem = MakeGrid(90, 70, Sines);
  dem.geometry.cell_y = 10;  // rows run northwards
  BuildAndCheck(dem, 2);
}

// Large enough for the builder's two threads (errors, selection, emission), with what each of
// them must get right at once: rows running northwards (mirrored orientation), a padded lattice
// (601 x 410 in 1025^2) and nodata holes, one of them across the roots' shared diagonal.
TEST(RtinBuilderTest, LargeSouthUpGridWithNodataOnTwoThreads) {
  Grid dem = MakeGrid(601, 410, [](double x, double y) {
    if (std::hypot(x - 2000.0, y + 2000.0) < 300) return kNaN;
    if (std::fmod(x - 7 * y, 1900.0) < 40) return kNaN;  // y < 0: x - 7 y > 0
    return Sines(x, y);
  });
  dem.geometry.cell_y = 10;
  for (double tolerance : {0.5, 4.0}) {
    Tin tin;
    const RtinReport report = BuildAndCheck(dem, tolerance, &tin);
    EXPECT_EQ(report.lattice_size, 1025);
    EXPECT_GT(testing::HiddenTriangles(tin), 0);
  }
}

TEST(RtinBuilderTest, RejectsBadInput) {
  const Grid dem = MakeGrid(10, 10, Sines);
  for (double tolerance : {-0.5, kNaN, std::numeric_limits<double>::infinity()}) {
    auto tin = BuildRtinTin(dem, {.tolerance = tolerance});
    ASSERT_FALSE(tin.ok());
    EXPECT_EQ(tin.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(tin.status().message().find("tolerance"), std::string::npos)
        << tin.status().message();
  }
  auto empty = BuildRtinTin(Grid{}, {.tolerance = 1});
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.status().message().find("empty"), std::string::npos);

  auto line = BuildRtinTin(MakeGrid(1, 50, Sines), {.tolerance = 1});
  ASSERT_FALSE(line.ok());
  EXPECT_NE(line.status().message().find("2 x 2"), std::string::npos);

  auto all_nan = BuildRtinTin(MakeGrid(20, 20, [](double, double) { return kNaN; }), {});
  ASSERT_FALSE(all_nan.ok());
  EXPECT_NE(all_nan.status().message().find("no valid cell"), std::string::npos);

  Grid huge;
  huge.geometry = GridGeometry{0, 0, 1, -1, kRtinMaxSide + 1, 2};
  auto too_wide = BuildRtinTin(huge, {});
  ASSERT_FALSE(too_wide.ok());
  EXPECT_NE(too_wide.status().message().find("tile it"), std::string::npos);
}

void CheckRealDem(const std::string& relative, std::initializer_list<double> tolerances) {
  auto dem = testing::ReadGridWithGdal(DataPath(relative));
  ASSERT_TRUE(dem.ok()) << dem.status().ToString();
  int64_t previous = std::numeric_limits<int64_t>::max();
  for (double tolerance : tolerances) {
    const auto start = std::chrono::steady_clock::now();
    RtinReport report;
    auto tin = BuildRtinTin(*dem, {.tolerance = tolerance}, &report);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_TRUE(tin.ok()) << tin.status().ToString();
    std::printf("%s at %.1f m: %lld points, %lld triangles, max %.3f m, rms %.3f m, %.2f s\n",
                relative.c_str(), tolerance, static_cast<long long>(report.points),
                static_cast<long long>(report.triangles), report.max_error, report.rms_error,
                seconds);
    ExpectValidRtin(*tin, *dem, tolerance, report);
    EXPECT_LT(report.triangles, previous) << "a coarser tolerance needs fewer triangles";
    previous = report.triangles;
  }
}

TEST(RtinBuilderTest, VinschgauDem) { CheckRealDem("dem/elev_vinschgau.tif", {1.0, 5.0, 20.0}); }

TEST(RtinBuilderTest, LuxembourgDemWithNodata) { CheckRealDem("dem/elev.tif", {1.0, 5.0}); }

TEST(RtinBuilderTest, SrtmN43E007) { CheckRealDem("dem/N43E007.hgt", {2.0, 10.0, 30.0}); }

// @mapbox/martini's mesh (index.js: Martini.createTile, Tile.getMesh), re-implemented here only
// to show what a bound over every covered cell buys: martini gives each diamond the error of
// its base midpoint against the hypotenuse, raised to its children's, and splits while that
// exceeds max_error. REQUIRES: a (2^k + 1)^2 grid without nodata.
class MartiniMesh {
 public:
  MartiniMesh(const Grid& dem, double max_error)
      : dem_(dem), n_(static_cast<int>(dem.geometry.width) - 1), max_error_(max_error) {
    errors_.assign(dem.cells.size(), 0);
    // Finest level first, so children's errors are final when a parent reads them.
    for (int depth = Depth(); depth >= 0; --depth) Visit(Root0(), 0, depth);
    for (int depth = Depth(); depth >= 0; --depth) Visit(Root1(), 0, depth);
  }

  Tin Build() {
    Tin tin;
    Select(Root0(), tin);
    Select(Root1(), tin);
    EXPECT_TRUE(LinkNeighbours(tin));
    return tin;
  }

 private:
  struct Tri {
    int ax, ay, bx, by, cx, cy;  // hypotenuse a-b, apex c
  };
  Tri Root0() const { return {0, 0, n_, n_, n_, 0}; }
  Tri Root1() const { return {n_, n_, 0, 0, 0, n_}; }
  int Depth() const { return 2 * static_cast<int>(std::log2(n_)); }
  float Z(int x, int y) const { return dem_.At(x, y); }
  float& Error(int x, int y) { return errors_[static_cast<size_t>(y) * (n_ + 1) + x]; }
  static bool Splittable(const Tri& t) { return (t.ax + t.bx) % 2 == 0 && (t.ay + t.by) % 2 == 0; }
  static std::pair<Tri, Tri> Children(const Tri& t) {
    const int mx = (t.ax + t.bx) / 2, my = (t.ay + t.by) / 2;
    return {Tri{t.cx, t.cy, t.ax, t.ay, mx, my}, Tri{t.bx, t.by, t.cx, t.cy, mx, my}};
  }

  void Visit(const Tri& t, int depth, int target) {
    if (!Splittable(t)) return;
    const auto [left, right] = Children(t);
    if (depth < target) {
      Visit(left, depth + 1, target);
      Visit(right, depth + 1, target);
      return;
    }
    const int mx = (t.ax + t.bx) / 2, my = (t.ay + t.by) / 2;
    float& e = Error(mx, my);
    e = std::max(e, std::fabs((Z(t.ax, t.ay) + Z(t.bx, t.by)) / 2 - Z(mx, my)));
    for (const Tri& c : {left, right}) {
      if (Splittable(c)) e = std::max(e, Error((c.ax + c.bx) / 2, (c.ay + c.by) / 2));
    }
  }

  void Select(const Tri& t, Tin& tin) {
    if (Splittable(t) && Error((t.ax + t.bx) / 2, (t.ay + t.by) / 2) > max_error_) {
      const auto [left, right] = Children(t);
      Select(left, tin);
      Select(right, tin);
      return;
    }
    TinTriangle tri;
    const int xs[3] = {t.ax, t.bx, t.cx}, ys[3] = {t.ay, t.by, t.cy};
    for (int i = 0; i < 3; ++i) {
      tri.v[i] = static_cast<uint32_t>(tin.vertices.size());
      tin.vertices.push_back({dem_.geometry.CellCenterX(xs[i]), dem_.geometry.CellCenterY(ys[i]),
                              Z(xs[i], ys[i]), VertexKind::kDem});
    }
    const TinVertex &a = tin.vertices[tri.v[0]], &b = tin.vertices[tri.v[1]],
                    &c = tin.vertices[tri.v[2]];
    if ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y) < 0) std::swap(tri.v[1], tri.v[2]);
    tin.triangles.push_back(tri);
  }

  const Grid& dem_;
  const int n_;
  const double max_error_;
  std::vector<float> errors_;
};

// mapbox/martini#21: martini's true error exceeds its nominal one (1.97 m at 1 m on a 4097^2
// terrain); on a real 257 x 257 SRTM window ours stays within the tolerance and martini does not.
TEST(RtinBuilderTest, TrueErrorBoundWhereMartiniOvershoots) {
  auto srtm = testing::ReadGridWithGdal(DataPath("dem/N43E007.hgt"));
  ASSERT_TRUE(srtm.ok()) << srtm.status().ToString();
  const Grid dem = testing::Window(*srtm, 100, 0, 257, 257);
  double worst_ratio = 0;
  for (double tolerance : {1.0, 2.0, 5.0, 10.0}) {
    const RtinReport ours = BuildAndCheck(dem, tolerance);
    const Tin martini_tin = MartiniMesh(dem, tolerance).Build();
    const double martini = FitToDem(martini_tin, dem).max_error;
    std::printf(
        "tolerance %4.1f m: ours %lld triangles, true max %.3f m; martini %zu triangles, "
        "true max %.3f m\n",
        tolerance, static_cast<long long>(ours.triangles), ours.max_error,
        martini_tin.triangles.size(), martini);
    worst_ratio = std::max(worst_ratio, martini / tolerance);
  }
  EXPECT_GT(worst_ratio, 1.0) << "martini's midpoint errors should understate the true error";
}

// Paper 000, Table 1: DEM simplification of 90000 points (300 x 300) at resolutions 0 to 2.5 m;
// points and triangles fall as the threshold rises. Here on a real SRTM window of the Alpes
// maritimes north of Nice (44.00-43.75 N, 7.08-7.33 E; all land, 49-1785 m), 90 m cells.
TEST(RtinBuilderTest, PaperTable1Shape) {
  auto srtm = testing::ReadGridWithGdal(DataPath("dem/N43E007.hgt"));
  ASSERT_TRUE(srtm.ok()) << srtm.status().ToString();
  const Grid dem = testing::Window(*srtm, 100, 0, 300, 300);
  ASSERT_EQ(dem.cells.size(), 90000u);
  std::printf("Resolution\tPoint\tTriangle\tMax error\tTime(s)\n");
  int64_t previous_points = std::numeric_limits<int64_t>::max();
  int64_t previous_triangles = std::numeric_limits<int64_t>::max();
  for (double threshold : {0.0, 0.5, 1.0, 1.5, 2.0, 2.5}) {
    const auto start = std::chrono::steady_clock::now();
    RtinReport report;
    auto tin = BuildRtinTin(dem, {.tolerance = threshold}, &report);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_TRUE(tin.ok()) << tin.status().ToString();
    std::printf("%.1f\t\t%lld\t%lld\t\t%.3f\t\t%.3f\n", threshold,
                static_cast<long long>(report.points), static_cast<long long>(report.triangles),
                report.max_error, seconds);
    ExpectValidRtin(*tin, dem, threshold, report);
    EXPECT_LT(report.points, previous_points);
    EXPECT_LT(report.triangles, previous_triangles);
    previous_points = report.points;
    previous_triangles = report.triangles;
  }
}

}  // namespace
}  // namespace tinbase
