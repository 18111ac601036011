// BoxOnData: a box is on data when every cell any of its points falls in holds data, with the
// cells found as CentroidCell finds a centroid's (a north-up grid: rows grow southwards).
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

}  // namespace
}  // namespace tinbase
