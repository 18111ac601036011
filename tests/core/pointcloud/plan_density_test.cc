// CountPointsWithinPlanRadius against a brute-force count: random clouds at projected
// coordinates (hundreds of kilometres from the origin), clusters, boundary distances, and z that
// must not matter.
#include "core/pointcloud/plan_density.h"

#include <gtest/gtest.h>

#include <random>

namespace tinbase {
namespace {

std::vector<uint32_t> BruteForceCounts(const std::vector<TinVertex>& points, double radius) {
  std::vector<uint32_t> counts(points.size(), 0);
  for (size_t i = 0; i < points.size(); ++i) {
    for (const TinVertex& q : points) {
      const double dx = q.x - points[i].x, dy = q.y - points[i].y;
      if (dx * dx + dy * dy <= radius * radius) ++counts[i];
    }
  }
  return counts;
}

TEST(PlanDensity, MatchesBruteForceOnRandomCloudsFarFromTheOrigin) {
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> coord(0, 200), z(-50, 900);
    std::normal_distribution<double> cluster(0, 3);
    std::vector<TinVertex> points;
    for (int i = 0; i < 1500; ++i) {
      points.push_back({500000 + coord(rng), 6200000 + coord(rng), z(rng), VertexKind::kLidar});
    }
    for (int i = 0; i < 500; ++i) {  // a dense patch, as where two passes overlap
      points.push_back({500100 + cluster(rng), 6200050 + cluster(rng), z(rng), VertexKind::kLidar});
    }
    for (double radius : {0.5, 2.0, 7.0, 40.0}) {
      EXPECT_EQ(CountPointsWithinPlanRadius(points, radius), BruteForceCounts(points, radius))
          << "seed " << seed << ", radius " << radius;
    }
  }
}

TEST(PlanDensity, PointsExactlyAtTheRadiusCount) {
  // A unit grid: an inner point has itself and its four edge neighbours at distance exactly 1.
  std::vector<TinVertex> grid;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j)
      grid.push_back({300000.0 + i, 4000000.0 + j, 0, VertexKind::kLidar});
  }
  const std::vector<uint32_t> counts = CountPointsWithinPlanRadius(grid, 1.0);
  EXPECT_EQ(counts[2 * 5 + 2], 5u);  // centre
  EXPECT_EQ(counts[0], 3u);          // corner
  EXPECT_EQ(counts[2], 4u);          // middle of an edge
  EXPECT_EQ(counts, BruteForceCounts(grid, 1.0));
}

TEST(PlanDensity, CountsInPlanWhateverTheHeights) {
  std::vector<TinVertex> column = {{10, 10, 0, VertexKind::kLidar},
                                   {10, 10.5, 1000, VertexKind::kLidar},
                                   {10, 12, -1000, VertexKind::kLidar}};
  EXPECT_EQ(CountPointsWithinPlanRadius(column, 1.0), (std::vector<uint32_t>{2, 2, 1}));
  EXPECT_TRUE(CountPointsWithinPlanRadius({}, 1.0).empty());
}

}  // namespace
}  // namespace tinbase
