// The seam a split refinement cuts along (core/tin/split_refinement.h): the line with the
// shortest chain near the one that splits the work evenly, and no split when even that chain is
// short and the caller asks so.
// The bound of split results is checked cell by cell in greedy_builder_test.cc.
#include "core/tin/split_refinement.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <functional>

#include "tests/support/thread_count.h"

namespace tinbase {
namespace {

// A width x height grid with 10 m cells, cell values f(col, row).
Grid MakeGrid(int64_t width, int64_t height, const std::function<double(int64_t, int64_t)>& f) {
  Grid grid;
  grid.geometry = GridGeometry{500000.0, 5200000.0, 10.0, -10.0, width, height};
  grid.cells.resize(static_cast<size_t>(width * height));
  for (int64_t r = 0; r < height; ++r)
    for (int64_t c = 0; c < width; ++c)
      grid.cells[static_cast<size_t>(r * width + c)] = static_cast<float>(f(c, r));
  return grid;
}

// A plane (every line's chain is its two ends) with a zigzag of 50 m down one line.
Grid PlaneWithZigzag(int64_t width, int64_t height, bool vertical, int64_t at) {
  return MakeGrid(width, height, [=](int64_t c, int64_t r) {
    const double plane = 100 + 0.5 * static_cast<double>(c) + 0.25 * static_cast<double>(r);
    const int64_t line = vertical ? c : r, along = vertical ? r : c;
    return line == at ? plane + 50.0 * static_cast<double>(along % 2) : plane;
  });
}

BoundaryElevationFn CellValue(const Grid& dem) {
  return [&dem](int64_t col, int64_t row) { return static_cast<double>(dem.At(col, row)); };
}

TEST(SplitRefinementTest, SeamAvoidsABusyMiddleColumn) {
  // 401 columns: the middle is column 200, lines are tried 2 apart up to 20 away.
  const Grid dem = PlaneWithZigzag(401, 300, /*vertical=*/true, 200);
  const SeamChoice seam = ChooseSeam(dem, 1.0, CellValue(dem));
  EXPECT_TRUE(seam.vertical);
  EXPECT_EQ(std::abs(seam.at - 200), 2);  // the nearest line tried with the shortest chain
  EXPECT_EQ(seam.chain_vertices, 2u);
}

TEST(SplitRefinementTest, SeamStaysInTheMiddleWhenNoLineIsShorter) {
  const Grid dem = PlaneWithZigzag(401, 300, /*vertical=*/true, -1);
  const SeamChoice seam = ChooseSeam(dem, 1.0, CellValue(dem));
  EXPECT_TRUE(seam.vertical);
  EXPECT_EQ(seam.at, 200);
  EXPECT_EQ(seam.chain_vertices, 2u);
}

TEST(SplitRefinementTest, SeamCrossesTheLongerSideWithinATwentiethOfTheMiddle) {
  // Taller than wide: the seam is a row; the zigzag runs along the middle row, so the seam
  // moves off it, but no further than 1/20 of the height.
  const Grid dem = PlaneWithZigzag(200, 1001, /*vertical=*/false, 500);
  const SeamChoice seam = ChooseSeam(dem, 1.0, CellValue(dem));
  EXPECT_FALSE(seam.vertical);
  EXPECT_NE(seam.at, 500);
  EXPECT_LE(std::abs(seam.at - 500), 1001 / 20);
  EXPECT_EQ(seam.chain_vertices, 2u);
}

TEST(SplitRefinementTest, SeamMovesToWhereTheWorkSplitsEvenly) {
  // Rough in the first 100 of 401 columns (a checkerboard of 50 m: every cell a vertex), a plane
  // elsewhere: nearly all the work lies west of column 100, so the seam does too.
  const Grid dem = MakeGrid(401, 300, [](int64_t c, int64_t r) {
    const double plane = 100 + 0.5 * static_cast<double>(c) + 0.25 * static_cast<double>(r);
    return c < 100 ? plane + 50.0 * static_cast<double>((c + r) % 2) : plane;
  });
  const SeamChoice seam = ChooseSeam(dem, 1.0, CellValue(dem));
  EXPECT_TRUE(seam.vertical);
  EXPECT_GE(seam.at, 1);
  EXPECT_LT(seam.at, 100);
}

// The automatic minimum grows with the seam (the grid's shorter side) past kMinSeamVertices.
TEST(SplitRefinementTest, MinimumChainGrowsWithTheSeam) {
  const auto minimum = [](int64_t width, int64_t height) {
    return MinSeamVertices(GridGeometry{0.0, 0.0, 1.0, -1.0, width, height});
  };
  EXPECT_EQ(minimum(1025, 1025), kMinSeamVertices);
  EXPECT_EQ(minimum(8000, 1000), kMinSeamVertices);  // the seam runs along the 1000 rows
  EXPECT_EQ(minimum(4097, 4097), 4097u / kMaxSeamCellsPerVertex);
  EXPECT_EQ(minimum(8000, 4000), 4000u / kMaxSeamCellsPerVertex);
}

TEST(SplitRefinementTest, ShortSeamKeepsTheGridWholeOnlyWhenAsked) {
  // Every line of a plane has a chain of 2: below any useful minimum.
  const Grid dem = PlaneWithZigzag(300, 300, /*vertical=*/true, -1);
  EXPECT_FALSE(RefineInHalves(dem, 1.0, CellValue(dem), kMinSeamVertices).has_value());
  const std::optional<Cdt> split = RefineInHalves(dem, 1.0, CellValue(dem));
  ASSERT_TRUE(split.has_value());
  // The four corners and the seam's two ends: a plane needs nothing more.
  EXPECT_EQ(split->vertices().size(), 6u);
}

// The halves refined side by side or one after the other, then joined and refined again: the
// same triangulation, vertex for vertex in the same order, on 1, 2 and 4 threads.
TEST(SplitRefinementTest, SameTriangulationOnAnyNumberOfThreads) {
  const Grid dem = MakeGrid(400, 260, [](int64_t c, int64_t r) {
    return 300 +
           40 * std::sin(static_cast<double>(c) / 17) * std::cos(static_cast<double>(r) / 23) +
           static_cast<double>((c * 7 + r * 13) % 5);
  });
  for (const double tolerance : {1.0, 8.0}) {
    SCOPED_TRACE("tolerance " + std::to_string(tolerance));
    const auto refine = [&](int threads) {
      std::optional<Cdt> cdt = testing::WithThreads(
          threads, [&] { return RefineInHalves(dem, tolerance, CellValue(dem)); });
      EXPECT_TRUE(cdt.has_value());
      return cdt ? cdt->ToTin() : Tin();
    };
    const Tin want = refine(1);
    ASSERT_GT(want.vertices.size(), 100u);
    for (int threads : testing::kThreadCounts) {
      SCOPED_TRACE(std::to_string(threads) + " threads");
      testing::ExpectSameTin(refine(threads), want);
    }
  }
}

}  // namespace
}  // namespace tinbase
