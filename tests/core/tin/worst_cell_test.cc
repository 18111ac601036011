// WorstCell: the vectorised run scan finds exactly the cell a plain cell-by-cell scan keeping the
// first strict maximum finds (ties included, nodata holes, spans cut short as a block-streamed
// source cuts them), and refinement with parallel scans inserts exactly the same points.
#include "core/tin/worst_cell.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/geometry/cdt.h"
#include "core/tin/tolerance_refiner.h"
#include "tests/support/terrain_grids.h"
#include "tests/support/thread_count.h"

namespace tinbase {
namespace {

using testing::MakeGrid;
using testing::Sines;

// Whole-metre heights (ties everywhere, as SRTM's) with nodata holes: a disc and every 13th cell
// of every 5th row.
Grid TerrainWithHoles(int64_t width, int64_t height) {
  Grid grid = MakeGrid(width, height, [](double x, double y) { return std::round(Sines(x, y)); });
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const int64_t hole_column = width / 3, hole_row = height / 2;
  for (int64_t r = 0; r < height; ++r) {
    for (int64_t c = 0; c < width; ++c) {
      const double dc = static_cast<double>(c - hole_column),
                   dr = static_cast<double>(r - hole_row);
      if (dc * dc + dr * dr < 40 || (r % 5 == 0 && c % 13 == 0))
        grid.cells[static_cast<size_t>(r * width + c)] = nan;
    }
  }
  return grid;
}

// The same cells, served in runs that stop at every 7th column, as a source reading blocks does.
class ShortRunSource final : public CellSource {
 public:
  explicit ShortRunSource(const Grid& grid) : grid_(grid) {}
  const GridGeometry& geometry() const override { return grid_.geometry; }
  const float* Span(int64_t row, int64_t col, int64_t* last) override {
    *last = std::min(*last, (col / 7) * 7 + 6);
    return grid_.cells.data() + row * grid_.geometry.width + col;
  }

 private:
  const Grid& grid_;
};

// The reference: every cell of the spans in order, the first strict maximum above the floor.
WorstCell PlainWorstCell(const Grid& grid, const CellTriangle& t, const CellPlane& plane,
                         double floor) {
  WorstCell worst{floor};
  ForEachCellSpan(
      t, grid.geometry.width, grid.geometry.height, [&](int64_t r, int64_t first, int64_t last) {
        for (int64_t c = first; c <= last; ++c) {
          const float value = grid.At(c, r);
          if (std::isnan(value)) continue;
          const double error =
              std::fabs(plane.At(static_cast<double>(c), static_cast<double>(r)) - value);
          if (error > worst.error) worst = WorstCell{error, c, r};
        }
      });
  return worst;
}

TEST(WorstCellTest, RunScanFindsThePlainScansCell) {
  const Grid grid = TerrainWithHoles(157, 131);
  GridCellSource whole(grid);
  ShortRunSource runs(grid);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> at(-10, 165), z(250, 350);
  int found = 0;
  for (int trial = 0; trial < 400; ++trial) {
    CellTriangle t;
    for (int i = 0; i < 3; ++i) t.col[i] = at(rng), t.row[i] = at(rng), t.z[i] = z(rng);
    // A flat plane at a whole metre: many cells tie at the largest error.
    if (trial % 4 == 0) t.z = {300, 300, 300};
    CellPlane plane;
    if (!PlaneOf(t, &plane)) continue;
    const double floor = trial % 3 == 0 ? 0.5 : 5;
    const WorstCell want = PlainWorstCell(grid, t, plane, floor);
    for (CellSource* source : {static_cast<CellSource*>(&whole), static_cast<CellSource*>(&runs)}) {
      WorstCell got{floor};
      const auto [row_min, row_max] = CellSpanRows(t, grid.geometry.height);
      RaiseToWorstInRows(*source, t, plane, row_min, row_max, &got);
      ASSERT_EQ(got.col, want.col) << "trial " << trial;
      ASSERT_EQ(got.row, want.row) << "trial " << trial;
      ASSERT_EQ(got.error, want.error) << "trial " << trial;
    }
    found += want.col >= 0;
  }
  EXPECT_GT(found, 100);  // most triangles have a cell beyond the floor
}

TEST(WorstCellTest, RowRangesTogetherAreTheWholeScan) {
  const Grid grid = TerrainWithHoles(90, 80);
  GridCellSource source(grid);
  const CellTriangle t{{-3, 95, 20}, {2, 10, 85}, {280, 350, 310}};
  CellPlane plane;
  ASSERT_TRUE(PlaneOf(t, &plane));
  const WorstCell want = PlainWorstCell(grid, t, plane, 1);
  ASSERT_GE(want.col, 0);
  for (int64_t middle : {want.row - 1, want.row, want.row + 1}) {
    WorstCell upper{1}, lower{1};
    RaiseToWorstInRows(source, t, plane, 0, middle, &upper);
    RaiseToWorstInRows(source, t, plane, middle + 1, grid.geometry.height - 1, &lower);
    const WorstCell got = lower.error > upper.error ? lower : upper;
    EXPECT_EQ(got.col, want.col);
    EXPECT_EQ(got.row, want.row);
  }
}

// Faces over more than 2^17 cells are scanned by ranges of rows on several threads (a 700 x 700
// grid's first faces are), and the faces of an insertion over 2^10 cells together by faces: the
// same points in the same order as without sharing, on 1, 2 and 4 threads.
TEST(WorstCellTest, ParallelScansInsertTheSamePoints) {
  const Grid grid = TerrainWithHoles(700, 700);
  const auto refine = [&](bool parallel, int threads) {
    Cdt cdt;
    const GridGeometry& g = grid.geometry;
    cdt.InsertVertices({{g.CellCenterX(0), g.CellCenterY(0), 300, VertexKind::kDem},
                        {g.CellCenterX(699), g.CellCenterY(0), 300, VertexKind::kDem},
                        {g.CellCenterX(0), g.CellCenterY(699), 300, VertexKind::kDem},
                        {g.CellCenterX(699), g.CellCenterY(699), 300, VertexKind::kDem}});
    RefineOptions options;
    options.tolerance = 8;
    options.parallel_scans = parallel;
    testing::WithThreads(threads, [&] { RefineToTolerance(cdt, grid, options); });
    return cdt.vertices();
  };
  const std::vector<TinVertex> one = refine(false, 1);
  ASSERT_GT(one.size(), 100u);
  for (int threads : testing::kThreadCounts) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    const std::vector<TinVertex> shared = refine(true, threads);
    ASSERT_EQ(one.size(), shared.size());
    for (size_t i = 0; i < one.size(); ++i) {
      EXPECT_EQ(one[i].x, shared[i].x) << i;
      EXPECT_EQ(one[i].y, shared[i].y) << i;
    }
  }
}

}  // namespace
}  // namespace tinbase
