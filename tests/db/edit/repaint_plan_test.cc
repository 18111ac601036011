// PlanRepaint for a fill far larger than the surface's blocks: blocks no ring comes near whose
// centre the fill holds are repainted whole with the fill's paint, blocks along the ring are read
// and painted triangle by triangle, blocks outside keep their paint; UniformBlockRepaints lists
// exactly the triangles of the uniform blocks (checked against the block index).
#include "db/edit/repaint_plan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <unordered_set>
#include <vector>

#include "core/tin/block_grid.h"
#include "db/feature_store.h"
#include "tests/support/edit_fixture.h"

namespace tinbase {
namespace {

using testing::kEditCell;
using testing::kEditCx;
using testing::kEditCy;
using testing::Ngon;

class RepaintPlanTest : public testing::EditFixture {};

TEST_F(RepaintPlanTest, LargeFillIsUniformInsideMixedAlongItsRing) {
  const LocalEdit edit = AddRing(Ngon(kEditCx, kEditCy, 30 * kEditCell, 40), 7, "unit");
  const EditorFeature& fill = edit.features[0];
  auto plan = PlanRepaint(Context(), edit, {});
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  ASSERT_GT(plan->uniform_blocks.size(), 4u);
  ASSERT_EQ(plan->uniform_paint.visible.size(), plan->uniform_blocks.size());
  EXPECT_TRUE(std::is_sorted(plan->uniform_blocks.begin(), plan->uniform_blocks.end()));
  EXPECT_EQ(plan->uniform_tags, std::vector<std::string>{"unit"});
  EXPECT_TRUE(plan->outside_keeps_paint);
  ASSERT_NE(plan->changed_inside, nullptr);
  const BlockGrid& g = surface_.blocks;
  const std::vector<int64_t>& near_ring = RingBlocksOf(fill, g);
  for (size_t k = 0; k < plan->uniform_blocks.size(); ++k) {
    const int64_t block = plan->uniform_blocks[k];
    const double cx =
        g.origin_x + (static_cast<double>(BlockGrid::ColumnOfPacked(block)) + 0.5) * g.size;
    const double cy =
        g.origin_y + (static_cast<double>(BlockGrid::RowOfPacked(block)) + 0.5) * g.size;
    EXPECT_NE(InsideOf(fill)->Locate({cx, cy}), PointInPolygon::kOutside) << "block " << block;
    EXPECT_FALSE(std::binary_search(near_ring.begin(), near_ring.end(), block))
        << "block " << block << " is near the ring but uniform";
    EXPECT_EQ(plan->uniform_paint.visible[k], 1);
    EXPECT_EQ(plan->uniform_paint.tag[k], 0);
  }
  // The triangles read one by one lie in blocks that are not uniform, near the ring.
  ASSERT_FALSE(plan->around.empty());
  const std::set<int64_t> uniform(plan->uniform_blocks.begin(), plan->uniform_blocks.end());
  std::set<int64_t> around_blocks;
  for (int64_t t : plan->around) {
    auto tri = mesh_->Triangle(t);
    ASSERT_TRUE(tri.ok());
    EXPECT_FALSE(uniform.count((*tri)->block)) << "triangle " << t;
    around_blocks.insert((*tri)->block);
  }
  for (int64_t block : around_blocks)
    EXPECT_TRUE(std::binary_search(near_ring.begin(), near_ring.end(), block))
        << "block " << block << " is read though no ring comes near";
  EXPECT_TRUE(plan->paint_box.Contains({edit.changed.min_x, edit.changed.min_y}));
  EXPECT_TRUE(plan->paint_box.Contains({edit.changed.max_x, edit.changed.max_y}));

  // The uniform blocks' triangles, less the ones the edit deletes, each with the fill's paint.
  std::unordered_set<int64_t> deleted;
  MeshDelta delta;  // no new triangles
  auto all = UniformBlockRepaints(Context(), *plan, deleted, delta);
  ASSERT_TRUE(all.ok()) << all.status().ToString();
  int64_t expected = 0;
  for (int64_t block : plan->uniform_blocks) {
    auto n = store_->db().QueryInt("SELECT count(*) FROM triangles WHERE block = " +
                                   std::to_string(block));
    ASSERT_TRUE(n.ok());
    expected += *n;
  }
  ASSERT_EQ(static_cast<int64_t>(all->size()), expected);
  auto tag = store_->db().QueryInt("SELECT id FROM tags WHERE value = 'unit'");
  ASSERT_TRUE(tag.ok()) << "the tag was not interned";
  for (size_t k = 0; k < all->size(); ++k) {
    if (k > 0) {
      EXPECT_LT((*all)[k - 1].triangle, (*all)[k].triangle);
    }
    EXPECT_TRUE((*all)[k].visible);
    EXPECT_EQ((*all)[k].tag, *tag);
  }
  deleted.insert((*all)[0].triangle);
  auto fewer = UniformBlockRepaints(Context(), *plan, deleted, delta);
  ASSERT_TRUE(fewer.ok());
  EXPECT_EQ(fewer->size() + 1, all->size());
  EXPECT_NE(fewer->front().triangle, (*all)[0].triangle);
}

TEST_F(RepaintPlanTest, NothingChangedPlansNothingAndTheWholeSurfacePlansItsBox) {
  LocalEdit edit;
  auto plan = PlanRepaint(Context(), edit, {});
  ASSERT_TRUE(plan.ok());
  EXPECT_TRUE(plan->paint_box.empty());
  EXPECT_TRUE(plan->around.empty());
  EXPECT_TRUE(plan->uniform_blocks.empty());
  EXPECT_EQ(plan->changed_inside, nullptr);

  edit = AddRing(Ngon(kEditCx, kEditCy, 3 * kEditCell, 9), 7);
  const RepaintPlan whole = WholeSurfaceRepaintPlan(edit);
  EXPECT_EQ(whole.paint_box.min_x, edit.changed.min_x);
  EXPECT_EQ(whole.paint_box.max_y, edit.changed.max_y);
  EXPECT_TRUE(whole.around.empty());
  EXPECT_TRUE(whole.uniform_blocks.empty());
}

}  // namespace
}  // namespace tinbase
