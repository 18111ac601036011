// RingBlocks on a 10 x 10 window of 10-unit blocks: the blocks a ring passes through or touches
// are near, blocks inside or outside it are not, a long diagonal marks only the blocks it
// crosses, and rings or parts of rings outside the window are ignored; the blocks found once for
// the whole grid (BlocksNearRings) mark the same blocks in any window.
#include "core/tin/ring_blocks.h"

#include <gtest/gtest.h>

#include <random>

namespace tinbase {
namespace {

const BlockGrid kGrid{0, 0, 10};

Polygon Square(double x0, double y0, double x1, double y1) {
  return {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, {}};
}

TEST(RingBlocksTest, BlocksTheRingPassesAreNearTheOthersNot) {
  RingBlocks blocks(kGrid, {0, 0, 9, 9});
  blocks.AddRings({Square(15, 15, 55, 55)});
  for (int64_t k = 1; k <= 5; ++k) {
    EXPECT_TRUE(blocks.Near(k, 1));
    EXPECT_TRUE(blocks.Near(1, k));
    EXPECT_TRUE(blocks.Near(k, 5));
    EXPECT_TRUE(blocks.Near(5, k));
  }
  for (int64_t by = 2; by <= 4; ++by)
    for (int64_t bx = 2; bx <= 4; ++bx) EXPECT_FALSE(blocks.Near(bx, by)) << bx << " " << by;
  EXPECT_FALSE(blocks.Near(0, 0));
  EXPECT_FALSE(blocks.Near(6, 3));
  EXPECT_FALSE(blocks.Near(9, 9));
  EXPECT_DOUBLE_EQ(blocks.Centre(3, 4).x, 35);
  EXPECT_DOUBLE_EQ(blocks.Centre(3, 4).y, 45);
}

TEST(RingBlocksTest, ARingOnABlockEdgeIsNearBothSidesAndTheMarginIsSmall) {
  RingBlocks on(kGrid, {0, 0, 9, 9});
  on.AddRings({Square(20, 20, 50, 50)});
  EXPECT_TRUE(on.Near(1, 2));  // x = 20 is the edge between columns 1 and 2
  EXPECT_TRUE(on.Near(2, 2));
  EXPECT_TRUE(on.Near(1, 1));  // the corner (20, 20) touches block (1, 1)
  EXPECT_FALSE(on.Near(3, 3));

  RingBlocks off(kGrid, {0, 0, 9, 9});
  off.AddRings({Square(19.5, 19.5, 50.5, 50.5)});  // half a unit off the edges: past the margin
  EXPECT_TRUE(off.Near(1, 2));
  EXPECT_FALSE(off.Near(2, 2));
  EXPECT_FALSE(off.Near(3, 3));
}

TEST(RingBlocksTest, ALongDiagonalMarksOnlyTheBlocksItCrosses) {
  RingBlocks blocks(kGrid, {0, 0, 9, 9});
  blocks.AddRings({Polygon{{{0.5, 0.5}, {99.5, 99.5}, {0.5, 99.5}}, {}}});
  for (int64_t k = 0; k <= 9; ++k) EXPECT_TRUE(blocks.Near(k, k));
  EXPECT_TRUE(blocks.Near(3, 2));   // the diagonal touches its corner (30, 30)
  EXPECT_FALSE(blocks.Near(4, 2));  // in the diagonal's box, away from it
  EXPECT_FALSE(blocks.Near(7, 2));
  EXPECT_FALSE(blocks.Near(2, 7));  // inside the triangle
}

TEST(RingBlocksTest, HolesCountAndRingsOutsideTheWindowAreIgnored) {
  RingBlocks blocks(kGrid, {2, 2, 4, 4});
  Polygon holed = Square(-100, -100, 200, 200);
  holed.holes.push_back({{32, 32}, {32, 38}, {38, 38}, {38, 32}});  // clockwise, inside (3, 3)
  blocks.AddRings({holed, Square(70, 70, 90, 90)});
  EXPECT_TRUE(blocks.Near(3, 3));
  EXPECT_FALSE(blocks.Near(2, 2));
  EXPECT_FALSE(blocks.Near(4, 4));
}

TEST(RingBlocksTest, BlocksFoundOnceMarkWhatTheRingsMarkInAnyWindow) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-20, 180);
  for (int round = 0; round < 20; ++round) {
    Polygon p;
    for (int i = 0; i < 12; ++i) p.shell.push_back({coordinate(rng), coordinate(rng)});
    p.holes.push_back({{60, 60}, {60, 70}, {70, 70}, {70, 60}});
    const std::vector<int64_t> once = BlocksNearRings(kGrid, {p});
    EXPECT_TRUE(std::is_sorted(once.begin(), once.end()));
    for (const BlockWindow& w : {BlockWindow{0, 0, 19, 19}, BlockWindow{3, 5, 8, 6},
                                 BlockWindow{6, 6, 6, 6}, BlockWindow{12, 0, 30, 30}}) {
      RingBlocks tested(kGrid, w), replayed(kGrid, w);
      tested.AddRings({p});
      replayed.AddBlocks(once);
      for (int64_t by = w.by0; by <= w.by1; ++by)
        for (int64_t bx = w.bx0; bx <= w.bx1; ++bx)
          ASSERT_EQ(tested.Near(bx, by), replayed.Near(bx, by)) << round << ": " << bx << " " << by;
    }
  }
  EXPECT_TRUE(BlocksNearRings(kGrid, {}).empty());
}

}  // namespace
}  // namespace tinbase
