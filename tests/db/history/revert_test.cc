// Feature versions, revert and as-of on the Hamersley surface: each edit writes the versions of
// the features it touched; a revert puts the features and the exact mesh back as they were
// (tests/db/history/surface_signature.h) with every invariant of the full check, falls back to
// re-refining (and says so) when a later edit replaced the rows, reverts points edits, and
// refuses unknown transactions, builds and conflicts with the store unchanged; --as-of reads the
// exact past without changing the store.
#include "db/history/revert.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "db/change_log.h"
#include "db/dem_store.h"
#include "db/edit/mass_points.h"
#include "db/history/as_of.h"
#include "db/history/feature_versions.h"
#include "db/polygon_editor.h"
#include "db/surface_builder.h"
#include "tests/db/history/surface_signature.h"
#include "tests/support/polygon_files.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::Ngon;
using testing::TempDir;

constexpr double kCx = 539300, kCy = 7497340, kCell = 344.404386931320971;

class RevertTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = Store::Create(Path(), "");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    DemStore dems(*store_);
    ASSERT_TRUE(dems.Import({testing::DataPath("geology/hamersley/dtm_rp.tif")}, {}).ok());
    SurfaceBuildOptions o;
    o.surface = "terrain";
    o.greedy.tolerance = 5;
    auto built = BuildSurfaceFromDem(*store_, o);
    ASSERT_TRUE(built.ok()) << built.status().ToString();
  }

  std::string Path() const { return dir_.Path("s.tinbase"); }

  PolygonAddReport Add(const std::string& name, const testing::PointList& ring,
                       FeatureMode mode = FeatureMode::kFill) {
    PolygonAddOptions o;
    o.surface = "terrain";
    o.file = testing::WritePolygons(dir_, name, {{ring}});
    o.mode = mode;
    o.tag = mode == FeatureMode::kFill ? name : "";
    if (mode == FeatureMode::kReplace) o.level = 450.25;  // no DEM cell has it
    auto report = AddPolygons(*store_, o);
    EXPECT_TRUE(report.ok()) << report.status().ToString();
    return report.ok() ? *report : PolygonAddReport{};
  }

  PolygonAddReport Update(int64_t id, const std::string& name, const testing::PointList& ring) {
    PolygonAddOptions o;
    o.file = testing::WritePolygons(dir_, name, {{ring}});
    auto report = UpdatePolygon(*store_, id, o);
    EXPECT_TRUE(report.ok()) << report.status().ToString();
    return report.ok() ? *report : PolygonAddReport{};
  }

  RevertReport Revert(int64_t tx, bool cascade = false) {
    RevertOptions options;
    options.cascade = cascade;
    auto report = RevertTransaction(*store_, tx, options);
    EXPECT_TRUE(report.ok()) << report.status().ToString();
    testing::ExpectStoreIntact(*store_, /*full=*/true);
    return report.ok() ? *report : RevertReport{};
  }

  // The store's rows, for "unchanged" (the store is closed and opened again around it).
  std::map<std::string, std::string> Checksums() {
    store_.reset();
    auto sums = testing::TableChecksums(Path());
    auto store = Store::Open(Path());
    EXPECT_TRUE(store.ok());
    store_ = std::move(*store);
    return sums;
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
};

TEST_F(RevertTest, EveryEditWritesTheVersionsOfTheFeaturesItTouched) {
  const PolygonAddReport a = Add("a.geojson", Ngon(kCx, kCy, 8 * kCell, 24));
  const PolygonAddReport b = Update(a.first_feature_id, "b.geojson", Ngon(kCx, kCy, 6 * kCell, 17));
  auto removed = RemovePolygon(*store_, b.first_feature_id);
  ASSERT_TRUE(removed.ok()) << removed.status().ToString();

  auto old_versions = VersionsOfFeature(*store_, a.first_feature_id);
  ASSERT_TRUE(old_versions.ok());
  ASSERT_EQ(old_versions->size(), 2u);
  EXPECT_TRUE((*old_versions)[0].present);
  EXPECT_EQ((*old_versions)[0].tx, a.tx);
  EXPECT_EQ((*old_versions)[0].action, "polygon add");
  EXPECT_FALSE((*old_versions)[1].present);
  EXPECT_EQ((*old_versions)[1].tx, b.tx);
  auto new_versions = VersionsOfFeature(*store_, b.first_feature_id);
  ASSERT_TRUE(new_versions.ok());
  ASSERT_EQ(new_versions->size(), 2u);
  EXPECT_EQ((*new_versions)[1].tx, removed->tx);
  EXPECT_FALSE((*new_versions)[1].present);
  EXPECT_EQ((*new_versions)[1].tag, "a.geojson") << "an update keeps the tag";

  auto changes = ChangesSince(*store_, a.tx - 1);
  ASSERT_TRUE(changes.ok());
  ASSERT_EQ(changes->size(), 3u);
  EXPECT_EQ((*changes)[0].features, std::vector<int64_t>{a.first_feature_id});
  EXPECT_EQ((*changes)[1].features, (std::vector<int64_t>{a.first_feature_id, b.first_feature_id}));
  EXPECT_EQ((*changes)[2].features, std::vector<int64_t>{b.first_feature_id});
}

// SQLite (and the PostgreSQL trigger) hand out 1 + the largest id, so the id of a removed last
// feature would come back for the next one and mix two features' histories.
TEST_F(RevertTest, AFreedIdIsNotGivenToAnotherFeature) {
  const PolygonAddReport a = Add("a.geojson", Ngon(kCx, kCy, 8 * kCell, 24));
  ASSERT_TRUE(RemovePolygon(*store_, a.first_feature_id).ok());
  const PolygonAddReport b = Add("b.geojson", Ngon(kCx + kCell, kCy, 5 * kCell, 13));
  EXPECT_GT(b.first_feature_id, a.first_feature_id);
  testing::ExpectStoreIntact(*store_, /*full=*/true);
}

TEST_F(RevertTest, RevertOfAnAddTakesTheSurfaceBack) {
  const testing::SurfaceSignature original = testing::SignatureOf(*store_);
  const PolygonAddReport a = Add("a.geojson", Ngon(kCx, kCy, 8 * kCell, 24), FeatureMode::kReplace);
  ASSERT_NE(testing::SignatureOf(*store_), original);
  ASSERT_GT(*store_->db().QueryInt("SELECT count(*) FROM vertices WHERE z = 450.25"), 0);
  const RevertReport r = Revert(a.tx);
  EXPECT_EQ(r.reverted, std::vector<int64_t>{a.tx});
  EXPECT_EQ(r.removed_features, std::vector<int64_t>{a.first_feature_id});
  EXPECT_TRUE(r.exact) << r.not_exact;
  testing::ExpectSameMesh(original, testing::SignatureOf(*store_), "after the revert");
  // Nothing of the replace polygon is left: no constraint, ring or crossing vertex, level or tag.
  const auto count = [&](const std::string& sql) { return *store_->db().QueryInt(sql); };
  EXPECT_EQ(count("SELECT count(*) FROM constraints"), 0);
  EXPECT_EQ(count("SELECT count(*) FROM vertices WHERE kind IN ('ring', 'steiner')"), 0);
  EXPECT_EQ(count("SELECT count(*) FROM vertices WHERE z = 450.25"), 0);
  EXPECT_EQ(count("SELECT count(*) FROM triangles WHERE tag IS NOT NULL"), 0);
  auto change = ChangeOf(*store_, r.transactions.at(0));
  ASSERT_TRUE(change.ok());
  EXPECT_EQ(change->action, std::string("revert ") + std::to_string(a.tx));
}

TEST_F(RevertTest, RevertOfARemoveOrUpdatePutsTheFeatureBackUnderItsId) {
  const PolygonAddReport a = Add("a.geojson", Ngon(kCx, kCy, 8 * kCell, 24));
  Add("e.geojson", Ngon(kCx + 5 * kCell, kCy, 6 * kCell, 19, 0.3), FeatureMode::kErase);
  const testing::SurfaceSignature with_a = testing::SignatureOf(*store_);
  auto removed = RemovePolygon(*store_, a.first_feature_id);
  ASSERT_TRUE(removed.ok());
  EXPECT_TRUE(Revert(removed->tx).exact);
  testing::ExpectSameMesh(with_a, testing::SignatureOf(*store_), "after reverting the remove");

  const PolygonAddReport b = Update(a.first_feature_id, "b.geojson", Ngon(kCx, kCy, 4 * kCell, 9));
  const testing::SurfaceSignature with_b = testing::SignatureOf(*store_);
  const RevertReport r = Revert(b.tx);
  EXPECT_EQ(r.restored_features, std::vector<int64_t>{a.first_feature_id});
  EXPECT_TRUE(r.exact) << r.not_exact;
  testing::ExpectSameMesh(with_a, testing::SignatureOf(*store_), "after reverting the update");
  // A revert is an edit like the others: reverting it redoes the update, exactly.
  EXPECT_TRUE(Revert(r.transactions.at(0)).exact);
  testing::ExpectSameMesh(with_b, testing::SignatureOf(*store_), "after reverting the revert");
  auto features = store_->db().QueryInt("SELECT count(*) FROM features WHERE id = " +
                                        std::to_string(b.first_feature_id));
  EXPECT_EQ(*features, 1);
}

TEST_F(RevertTest, RefusesUnknownTransactionsBuildsAndConflictsLeavingTheStoreUnchanged) {
  const testing::SurfaceSignature original = testing::SignatureOf(*store_);
  const PolygonAddReport a = Add("a.geojson", Ngon(kCx, kCy, 8 * kCell, 24));
  const PolygonAddReport b = Update(a.first_feature_id, "b.geojson", Ngon(kCx, kCy, 6 * kCell, 17));
  const auto before = Checksums();

  auto unknown = RevertTransaction(*store_, 999, {});
  EXPECT_EQ(unknown.status().code(), StatusCode::kNotFound);
  EXPECT_EQ(unknown.status().message(), "no transaction 999");
  auto build = RevertTransaction(*store_, 1, {});  // the DEM import and build come first
  EXPECT_EQ(build.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(build.status().message().find("is not an edit of features"), std::string::npos)
      << build.status().message();
  auto conflict = RevertTransaction(*store_, a.tx, {});
  EXPECT_EQ(conflict.status().code(), StatusCode::kConflict);
  EXPECT_NE(conflict.status().message().find("changed again by transaction " +
                                             std::to_string(b.tx) + " (polygon update)"),
            std::string::npos)
      << conflict.status().message();
  EXPECT_EQ(Checksums(), before);

  const RevertReport both = Revert(a.tx, /*cascade=*/true);
  EXPECT_EQ(both.reverted, (std::vector<int64_t>{a.tx, b.tx}));
  EXPECT_EQ(both.transactions.size(), 1u) << "a cascade is one transaction";
  EXPECT_TRUE(both.exact) << both.not_exact;
  testing::ExpectSameMesh(original, testing::SignatureOf(*store_), "after the cascade");
}

// Reverts in reverse order need no --cascade: a later edit that was itself reverted left the
// feature as it was.
TEST_F(RevertTest, RevertsInReverseOrderAreNoConflict) {
  const testing::SurfaceSignature original = testing::SignatureOf(*store_);
  const PolygonAddReport a = Add("a.geojson", Ngon(kCx, kCy, 8 * kCell, 24));
  const PolygonAddReport b = Update(a.first_feature_id, "b.geojson", Ngon(kCx, kCy, 6 * kCell, 17));
  EXPECT_TRUE(Revert(b.tx).exact);
  const RevertReport r = Revert(a.tx);
  EXPECT_EQ(r.reverted, std::vector<int64_t>{a.tx});
  EXPECT_TRUE(r.exact) << r.not_exact;
  testing::ExpectSameMesh(original, testing::SignatureOf(*store_), "after both reverts");
}

TEST_F(RevertTest, AsOfReadsThePastAndLeavesTheStoreUnchanged) {
  const PolygonAddReport a = Add("a.geojson", Ngon(kCx, kCy, 8 * kCell, 24));
  const testing::SurfaceSignature after_a = testing::SignatureOf(*store_);
  const PolygonAddReport b = Add("b.geojson", Ngon(kCx + 9 * kCell, kCy, 5 * kCell, 15));
  ASSERT_TRUE(RemovePolygon(*store_, a.first_feature_id).ok());
  const auto before = Checksums();
  auto surface = SurfaceStore(*store_).Find("terrain");
  ASSERT_TRUE(surface.ok());
  {
    auto past = BeginAsOf(*store_, *surface, a.tx);
    ASSERT_TRUE(past.ok()) << past.status().ToString();
    testing::ExpectSameMesh(after_a, testing::SignatureOf(*store_), "as of the first add");
  }
  EXPECT_EQ(Checksums(), before);

  auto future = BeginAsOf(*store_, *surface, b.tx + 100);
  EXPECT_EQ(future.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(future.status().message().find("in the future"), std::string::npos);
  EXPECT_EQ(Checksums(), before);
}

// A later edit of another feature that re-triangulated the rows the first edit wrote: the images
// no longer fit, so the revert re-refines the region, says why, and still gives back the features
// with every invariant.
TEST_F(RevertTest, ALaterEditOfTheSameRowsMakesTheRevertReRefine) {
  const PolygonAddReport a = Add("a.geojson", Ngon(kCx, kCy, 8 * kCell, 24));
  const PolygonAddReport b = Add("b.geojson", Ngon(kCx + 4 * kCell, kCy, 6 * kCell, 15));
  const RevertReport r = Revert(a.tx);
  EXPECT_FALSE(r.exact);
  EXPECT_NE(r.not_exact.find("transaction " + std::to_string(a.tx) +
                             " wrote were changed since by another edit"),
            std::string::npos)
      << r.not_exact;
  EXPECT_EQ(*store_->db().QueryInt("SELECT count(*) FROM features"), 1);
  EXPECT_EQ(*store_->db().QueryInt("SELECT id FROM features"), b.first_feature_id);
}

// Points edits write feature versions and mesh images like polygon edits: an add and a remove are
// each reverted to the exact mesh before them.
TEST_F(RevertTest, PointsAddAndRemoveAreRevertedExactly) {
  const testing::SurfaceSignature original = testing::SignatureOf(*store_);
  PointsAddOptions o;
  o.surface = "terrain";
  o.points =
      std::vector<TinVertex>{{kCx + 0.3 * kCell, kCy + 0.2 * kCell, 650.5, VertexKind::kUser},
                             {kCx - 2.1 * kCell, kCy + 1.4 * kCell, 640.25, VertexKind::kUser},
                             {kCx + 1.7 * kCell, kCy - 2.6 * kCell, 660.75, VertexKind::kUser}};
  o.labels = {"p1", "p2", "p3"};
  auto added = AddPoints(*store_, o);
  ASSERT_TRUE(added.ok()) << added.status().ToString();
  const testing::SurfaceSignature with_points = testing::SignatureOf(*store_);
  auto versions = VersionsOfFeature(*store_, added->features_added.at(0));
  ASSERT_TRUE(versions.ok());
  ASSERT_EQ(versions->size(), 1u);
  EXPECT_EQ(versions->front().mode, "points");

  PointsRemoveOptions remove;
  remove.feature = added->features_added.at(0);
  auto removed = RemovePoints(*store_, remove);
  ASSERT_TRUE(removed.ok()) << removed.status().ToString();
  const RevertReport back = Revert(removed->tx);
  EXPECT_TRUE(back.exact) << back.not_exact;
  EXPECT_EQ(back.restored_features, added->features_added);
  testing::ExpectSameMesh(with_points, testing::SignatureOf(*store_), "after reverting the remove");

  auto undo_add = RevertTransaction(*store_, added->tx, {});
  ASSERT_TRUE(undo_add.ok()) << undo_add.status().ToString();
  EXPECT_TRUE(undo_add->exact) << undo_add->not_exact;
  testing::ExpectStoreIntact(*store_, /*full=*/true);
  testing::ExpectSameMesh(original, testing::SignatureOf(*store_), "after reverting the add");
}

// Points edits whose rows a later polygon replaced: the revert takes the points out, or puts them
// back, through the points editor (their own z), says it is not exact, and keeps every invariant.
TEST_F(RevertTest, PointsRevertsWhoseRowsChangedGoThroughThePointsEditor) {
  PointsAddOptions o;
  o.surface = "terrain";
  o.points =
      std::vector<TinVertex>{{kCx + 0.3 * kCell, kCy + 0.2 * kCell, 650.5, VertexKind::kUser},
                             {kCx - 1.1 * kCell, kCy + 0.4 * kCell, 640.25, VertexKind::kUser}};
  o.labels = {"p1", "p2"};
  auto added = AddPoints(*store_, o);
  ASSERT_TRUE(added.ok()) << added.status().ToString();
  const auto user_vertices = [&] {
    return *store_->db().QueryInt("SELECT count(*) FROM vertices WHERE kind = 'user'");
  };
  ASSERT_EQ(user_vertices(), 2);
  Add("fill.geojson", Ngon(kCx, kCy, 3 * kCell, 11));
  const RevertReport out = Revert(added->tx);
  EXPECT_FALSE(out.exact);
  EXPECT_EQ(out.removed_features, added->features_added);
  EXPECT_EQ(user_vertices(), 0);

  // Undoing that revert puts them back (exactly: the revert kept its own image); then removed,
  // covered again, and the removal reverted: back through the points editor.
  EXPECT_TRUE(Revert(out.transactions.at(0)).exact);
  EXPECT_EQ(user_vertices(), 2);
  PointsRemoveOptions remove;
  remove.feature = added->features_added.at(0);
  auto removed = RemovePoints(*store_, remove);
  ASSERT_TRUE(removed.ok()) << removed.status().ToString();
  Add("erase.geojson", Ngon(kCx, kCy, 2 * kCell, 9), FeatureMode::kErase);
  const RevertReport back = Revert(removed->tx);
  EXPECT_FALSE(back.exact);
  EXPECT_EQ(back.restored_features, added->features_added);
  EXPECT_EQ(user_vertices(), 2);
  EXPECT_EQ(
      *store_->db().QueryInt("SELECT count(*) FROM vertices WHERE kind = 'user' AND z = 650.5"), 1);
}

}  // namespace
}  // namespace tinbase
