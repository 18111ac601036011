// The terrain builder dispatches to greedy, VIP, RTIN and edge collapse, says which results are
// Delaunay, and parses exactly the canonical method names.
#include "core/tin/terrain_builder.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "core/tin/edge_collapse.h"
#include "core/tin/greedy_builder.h"
#include "core/tin/grid_triangulation.h"
#include "core/tin/rtin_builder.h"
#include "core/tin/vip_builder.h"
#include "tests/support/lattice_tin_checks.h"
#include "tests/support/terrain_grids.h"
#include "tests/support/tin_checks.h"

namespace tinbase {
namespace {

using testing::MakeGrid;
using testing::Sines;

// Interior edges whose far vertex lies strictly inside the circumcircle.
int64_t NonDelaunayEdges(const Tin& tin) {
  int64_t count = 0;
  for (const TinTriangle& t : tin.triangles) {
    for (int i = 0; i < 3; ++i) {
      if (t.n[i] == kNoNeighbour) continue;
      const TinTriangle& other = tin.triangles[static_cast<size_t>(t.n[i])];
      uint32_t far = other.v[0];
      for (uint32_t w : other.v) {
        if (w != t.v[(i + 1) % 3] && w != t.v[(i + 2) % 3]) far = w;
      }
      count += CGAL::side_of_oriented_circle(
                   testing::PlanPoint(tin, t.v[0]), testing::PlanPoint(tin, t.v[1]),
                   testing::PlanPoint(tin, t.v[2]),
                   testing::PlanPoint(tin, far)) == CGAL::ON_POSITIVE_SIDE;
    }
  }
  return count;
}

TEST(TerrainBuilderTest, MethodNamesRoundTrip) {
  std::set<std::string> names;
  for (TerrainMethod m : kTerrainMethods) {
    names.insert(TerrainMethodName(m));
    auto parsed = ParseTerrainMethod(TerrainMethodName(m));
    ASSERT_TRUE(parsed.ok()) << parsed.status().ToString();
    EXPECT_EQ(*parsed, m);
  }
  EXPECT_EQ(names, (std::set<std::string>{"greedy", "vip", "rtin", "collapse"}));
}

TEST(TerrainBuilderTest, UnknownMethodNamesTheValueAndTheChoices) {
  for (const std::string bad : {"martini", "", "Greedy", "greedy ", "edge-collapse"}) {
    auto parsed = ParseTerrainMethod(bad);
    ASSERT_FALSE(parsed.ok()) << "'" << bad << "'";
    EXPECT_EQ(parsed.status().code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(parsed.status().message(),
              "unknown TIN method '" + bad + "' (expected greedy, vip, rtin or collapse)");
  }
}

TEST(TerrainBuilderTest, DispatchesAndSaysWhetherDelaunay) {
  const Grid dem = MakeGrid(150, 120, Sines);
  const double tolerance = 1.5;

  TerrainBuildReport report;
  auto greedy =
      BuildTerrainTin(dem, {.method = TerrainMethod::kGreedy, .tolerance = tolerance}, &report);
  ASSERT_TRUE(greedy.ok()) << greedy.status().ToString();
  auto direct_greedy = BuildGreedyTin(dem, {.tolerance = tolerance});
  ASSERT_TRUE(direct_greedy.ok());
  EXPECT_EQ(greedy->vertices.size(), direct_greedy->vertices.size());
  EXPECT_TRUE(report.delaunay);
  EXPECT_TRUE(report.within_tolerance);
  EXPECT_EQ(NonDelaunayEdges(*greedy), 0);
  EXPECT_LE(testing::FitToDem(*greedy, dem).max_error, tolerance + 1e-6);

  auto vip = BuildTerrainTin(dem, {.method = TerrainMethod::kVip, .threshold = 0.3}, &report);
  ASSERT_TRUE(vip.ok()) << vip.status().ToString();
  auto direct_vip = BuildVipTin(dem, {.threshold = 0.3});
  ASSERT_TRUE(direct_vip.ok());
  EXPECT_EQ(vip->vertices.size(), direct_vip->vertices.size());
  EXPECT_EQ(report.method, TerrainMethod::kVip);
  EXPECT_TRUE(report.delaunay);
  EXPECT_FALSE(report.within_tolerance);
  EXPECT_EQ(NonDelaunayEdges(*vip), 0);
  EXPECT_NEAR(report.max_error, testing::FitToDem(*vip, dem).max_error, 1e-6);

  auto rtin =
      BuildTerrainTin(dem, {.method = TerrainMethod::kRtin, .tolerance = tolerance}, &report);
  ASSERT_TRUE(rtin.ok()) << rtin.status().ToString();
  auto direct_rtin = BuildRtinTin(dem, {.tolerance = tolerance});
  ASSERT_TRUE(direct_rtin.ok());
  EXPECT_EQ(rtin->triangles.size(), direct_rtin->triangles.size());
  EXPECT_FALSE(report.delaunay);
  EXPECT_TRUE(report.within_tolerance);
  EXPECT_EQ(report.triangles, static_cast<int64_t>(rtin->triangles.size()));
  // On square cells a conforming binary tree passes the empty-circle test up to its ties; on
  // rectangular cells its triangles are no longer right-isosceles in the plane and it fails.
  Grid oblong = dem;
  oblong.geometry.cell_x = 30;
  auto stretched =
      BuildTerrainTin(oblong, {.method = TerrainMethod::kRtin, .tolerance = tolerance});
  ASSERT_TRUE(stretched.ok()) << stretched.status().ToString();
  EXPECT_GT(NonDelaunayEdges(*stretched), 0) << "an RTIN is not Delaunay: store it as free";
  EXPECT_LE(testing::FitToDem(*rtin, dem).max_error, tolerance + 1e-6);
  testing::ExpectTilesGridWithoutTJunctions(*rtin, dem);

  const CollapseOptions budget{.faces = 2000};
  auto collapse =
      BuildTerrainTin(dem, {.method = TerrainMethod::kCollapse, .collapse = budget}, &report);
  ASSERT_TRUE(collapse.ok()) << collapse.status().ToString();
  CollapseReport direct_report;
  auto direct_collapse = CollapseToFaceBudget(GridTriangulation(dem), budget, &direct_report, &dem);
  ASSERT_TRUE(direct_collapse.ok());
  EXPECT_EQ(collapse->triangles.size(), direct_collapse->triangles.size());
  EXPECT_EQ(report.method, TerrainMethod::kCollapse);
  EXPECT_FALSE(report.delaunay);
  EXPECT_FALSE(report.within_tolerance);
  EXPECT_TRUE(report.collapse.budget_met);
  EXPECT_EQ(report.triangles, static_cast<int64_t>(collapse->triangles.size()));
  EXPECT_DOUBLE_EQ(report.max_error, direct_report.max_error);
}

TEST(TerrainBuilderTest, GreedyStoppedByItsBudgetIsNotWithinTolerance) {
  const Grid dem = MakeGrid(150, 120, Sines);
  TerrainBuildReport report;
  auto tin = BuildTerrainTin(
      dem, {.method = TerrainMethod::kGreedy, .tolerance = 0.1, .max_points = 20}, &report);
  ASSERT_TRUE(tin.ok()) << tin.status().ToString();
  EXPECT_EQ(report.points, 20);
  EXPECT_FALSE(report.within_tolerance);
}

TEST(TerrainBuilderTest, RejectsWhatTheMethodRejects) {
  const Grid dem = MakeGrid(30, 30, Sines);
  auto rtin_budget =
      BuildTerrainTin(dem, {.method = TerrainMethod::kRtin, .tolerance = 1, .max_points = 100});
  ASSERT_FALSE(rtin_budget.ok());
  EXPECT_EQ(rtin_budget.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(rtin_budget.status().message().find("max_points"), std::string::npos);

  auto vip = BuildTerrainTin(dem, {.method = TerrainMethod::kVip, .threshold = -1});
  ASSERT_FALSE(vip.ok());
  EXPECT_NE(vip.status().message().find("VIP"), std::string::npos);

  auto greedy = BuildTerrainTin(dem, {.method = TerrainMethod::kGreedy, .tolerance = 0});
  ASSERT_FALSE(greedy.ok());
  EXPECT_NE(greedy.status().message().find("tolerance"), std::string::npos);
}

}  // namespace
}  // namespace tinbase
