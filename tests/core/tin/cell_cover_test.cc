// BoxOnData: a box is on data when every cell any of its points falls in holds data, with the
// cells found as CentroidCell finds a centroid's (a north-up grid: rows grow southwards).
// HoldsCellCentre: the exact test behind the rasteriser's margin.
#include "core/tin/cell_cover.h"

#include <gtest/gtest.h>

#include <limits>

namespace tinbase {
namespace {

Grid FourByFour() {
  Grid g;
  g.geometry = GridGeometry{0, 40, 10, -10, 4, 4};
  g.cells.assign(16, 1.0f);
  g.cells[1 * 4 + 2] = std::numeric_limits<float>::quiet_NaN();  // column 2, row 1
  return g;
}

TEST(BoxOnDataTest, EveryCellUnderTheBoxMustHoldData) {
  const Grid g = FourByFour();
  EXPECT_TRUE(BoxOnData(g, 1, 1, 15, 15));     // columns 0-1, rows 2-3
  EXPECT_FALSE(BoxOnData(g, 21, 21, 29, 29));  // column 2, row 1 only
  EXPECT_FALSE(BoxOnData(g, 15, 15, 25, 25));  // reaches into it
  EXPECT_TRUE(BoxOnData(g, 31, 1, 39, 39));    // column 3, all rows
  // A box reaching off the grid is not on data: a centroid there would not be.
  EXPECT_FALSE(BoxOnData(g, -1, 1, 5, 5));
  EXPECT_FALSE(BoxOnData(g, 1, 35, 5, 41));
}

TEST(BoxOnDataTest, AgreesWithTheCentroidTestOfATriangleInside) {
  const Grid g = FourByFour();
  const TinVertex a{22, 22, 0}, b{28, 22, 0}, c{25, 28, 0};
  EXPECT_FALSE(TriangleOnData(g, a, b, c));
  const TinVertex d{2, 2, 0}, e{8, 2, 0}, f{5, 8, 0};
  EXPECT_TRUE(TriangleOnData(g, d, e, f));
  EXPECT_TRUE(BoxOnData(g, 1, 1, 9, 9));
}

TEST(HoldsCellCentreTest, TheMarginAdmitsACentreTheTriangleDoesNotHold) {
  // Cell centres at x = 5, 15, 25, 35. The triangle's left edge runs 1e-10 cells east of the
  // centre (5, 15): the span's margin takes that centre, the exact test does not.
  const GridGeometry g{0, 40, 10, -10, 4, 4};
  const TinVertex a{5 + 1e-9, 5, 0}, b{35, 15, 0}, c{5 + 1e-9, 35, 0};
  ASSERT_EQ(g.CellCenterX(0), 5.0);
  ASSERT_EQ(g.CellCenterY(2), 15.0);
  bool spanned = false;
  ForEachCellSpan(ToCellSpace(g, a, b, c), 4, 4,
                  [&](int64_t row, int64_t first, int64_t) { spanned |= row == 2 && first == 0; });
  EXPECT_TRUE(spanned);
  EXPECT_FALSE(HoldsCellCentre(g, a, b, c, 0, 2));
  EXPECT_TRUE(HoldsCellCentre(g, a, b, c, 1, 2));
  // A centre on an edge or at a vertex is held.
  const TinVertex d{5, 5, 0}, e{35, 15, 0}, f{5, 35, 0};
  EXPECT_TRUE(HoldsCellCentre(g, d, e, f, 0, 2));
  EXPECT_TRUE(HoldsCellCentre(g, d, e, f, 0, 3));
}

}  // namespace
}  // namespace tinbase
