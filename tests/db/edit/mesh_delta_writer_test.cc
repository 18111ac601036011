// WriteMeshDelta and MeshCache::Apply on the delta of a real edit (a stored fill feature removed
// from a greedy surface of the Hamersley DEM): the store ends with exactly the delta's rows and
// passes the full check, the cache that the stages read through equals the store after applying
// the same delta, the seven write steps come in order, and a failure at any of them leaves the
// store as it was once the transaction rolls back.
#include "db/edit/mesh_delta_writer.h"

#include <gtest/gtest.h>

#include <vector>

#include "db/edit/mesh_delta_builder.h"
#include "db/feature_store.h"
#include "db/polygon_editor.h"
#include "tests/support/edit_fixture.h"
#include "tests/support/store_target.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::kEditCell;
using testing::kEditCx;
using testing::kEditCy;
using testing::Ngon;

class MeshDeltaWriterTest : public testing::EditFixture {
 protected:
  void SetUp() override {
    EditFixture::SetUp();
    PolygonAddOptions o;
    o.surface = "terrain";
    o.file =
        testing::WritePolygons(dir_, "fill.geojson", {{Ngon(kEditCx, kEditCy, 5 * kEditCell, 13)}});
    o.mode = FeatureMode::kFill;
    o.tag = "t";
    auto report = AddPolygons(*store_, o);
    ASSERT_TRUE(report.ok()) << report.status().ToString();
    feature_ = report->first_feature_id;
    ASSERT_TRUE(ReloadSurface());
  }

  // The delta that removes the fill, built through every stage with the fixture's cache.
  MeshDelta RemovalDelta() {
    LocalEdit edit;
    edit.remove = {feature_};
    auto feature = LoadFeature(*store_, surface_, feature_);
    EXPECT_TRUE(feature.ok());
    edit.changed = BoxOf(*feature);
    const EditContext ctx = Context();
    auto region = FindConflictRegion(ctx, edit);
    EXPECT_TRUE(region.ok()) << region.status().ToString();
    auto plan = PlanRepaint(ctx, edit, region->removed_features);
    EXPECT_TRUE(plan.ok()) << plan.status().ToString();
    const ElevationRules rules(*dems_, dem_, edit.features, region->restore);
    auto patch = RetriangulateUntilSettled(ctx, rules, plan->paint_box, edit.remove, &*region);
    EXPECT_TRUE(patch.ok()) << patch.status().ToString();
    auto delta = BuildMeshDelta(ctx, rules, edit, *region, *patch, *plan);
    EXPECT_TRUE(delta.ok()) << delta.status().ToString();
    return std::move(*delta);
  }

  int64_t Int(const std::string& sql) {
    auto n = store_->db().QueryInt(sql);
    EXPECT_TRUE(n.ok()) << sql;
    return n.ok() ? *n : -1;
  }

  int64_t feature_ = 0;
};

TEST_F(MeshDeltaWriterTest, WritesExactlyTheDeltaAndTheCacheFollows) {
  const int64_t triangles_before = Int("SELECT count(*) FROM triangles");
  auto tx = store_->BeginWrite();
  ASSERT_TRUE(tx.ok());
  const MeshDelta delta = RemovalDelta();
  ASSERT_FALSE(delta.new_triangles.empty());
  ASSERT_FALSE(delta.deleted_triangles.empty());
  ASSERT_FALSE(delta.relinked.empty());
  ASSERT_FALSE(delta.deleted_vertices.empty());  // the ring's own vertices
  EXPECT_EQ(delta.removed_features, std::vector<int64_t>{feature_});
  EXPECT_TRUE(delta.added_constraints.empty());
  EXPECT_FALSE(delta.whole_surface);
  std::vector<int> steps;
  auto repainted = WriteMeshDelta(store_->db(), surface_, delta, [&](int step) {
    steps.push_back(step);
    return Status::Ok();
  });
  ASSERT_TRUE(repainted.ok()) << repainted.status().ToString();
  EXPECT_EQ(steps, (std::vector<int>{1, 2, 3, 4, 5, 6, 7}));
  EXPECT_GT(*repainted, 0);  // the fill's inside outside R goes back to untagged

  EXPECT_EQ(Int("SELECT count(*) FROM triangles"),
            triangles_before + static_cast<int64_t>(delta.new_triangles.size()) -
                static_cast<int64_t>(delta.deleted_triangles.size()));
  for (int64_t t : delta.deleted_triangles)
    EXPECT_EQ(Int("SELECT count(*) FROM triangles WHERE id = " + std::to_string(t)), 0);
  for (int64_t v : delta.deleted_vertices)
    EXPECT_EQ(Int("SELECT count(*) FROM vertices WHERE id = " + std::to_string(v)), 0);
  for (size_t k = 0; k < delta.new_triangles.size(); ++k) {
    const std::string id = std::to_string(delta.first_triangle + static_cast<int64_t>(k));
    EXPECT_EQ(Int("SELECT v0 FROM triangles WHERE id = " + id), delta.new_triangles[k].v[0]);
    EXPECT_EQ(Int("SELECT block FROM triangles WHERE id = " + id), delta.new_triangles[k].block);
  }
  for (const auto& [id, row] : delta.relinked)
    for (int i = 0; i < 3; ++i)
      EXPECT_EQ(Int("SELECT coalesce(n" + std::to_string(i) +
                    ", 0) FROM triangles WHERE id = " + std::to_string(id)),
                row.n[i].value_or(0));
  EXPECT_EQ(Int("SELECT count(*) FROM constraints WHERE feature = " + std::to_string(feature_)), 0);

  mesh_->Apply(delta);
  ASSERT_TRUE(DeleteFeature(*store_, feature_).ok());
  ASSERT_TRUE((*tx)->Commit().ok());
  auto held = mesh_->Triangle(delta.first_triangle);
  ASSERT_TRUE(held.ok());
  EXPECT_EQ((*held)->v, delta.new_triangles[0].v);
  const Status same = mesh_->VerifyAgainstStore();
  EXPECT_TRUE(same.ok()) << same.ToString();
  testing::ExpectStoreIntact(*store_, /*full=*/true);
}

TEST_F(MeshDeltaWriterTest, AFailureAtAnyStepRollsEverythingBack) {
  Close(/*reopen=*/false);
  const auto before = testing::TableChecksums(testing::StoreTarget(dir_, "s.tinbase"));
  for (int fail_at = 1; fail_at <= 7; ++fail_at) {
    SCOPED_TRACE("failure at step " + std::to_string(fail_at));
    Close(/*reopen=*/true);
    {
      auto tx = store_->BeginWrite();
      ASSERT_TRUE(tx.ok());
      const MeshDelta delta = RemovalDelta();
      int last = 0;
      auto written = WriteMeshDelta(store_->db(), surface_, delta, [&](int step) {
        last = step;
        return step == fail_at ? Status::IOError("injected") : Status::Ok();
      });
      EXPECT_EQ(written.status().code(), StatusCode::kIOError);
      EXPECT_EQ(last, fail_at);
    }  // rolled back
    Close(/*reopen=*/false);
    EXPECT_EQ(testing::TableChecksums(testing::StoreTarget(dir_, "s.tinbase")), before);
  }
}

}  // namespace
}  // namespace tinbase
