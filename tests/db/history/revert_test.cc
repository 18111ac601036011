// Feature versions, revert and as-of on the Hamersley surface: each edit writes the versions of
// the features it touched; a revert puts the features back as they were (tests/db/history/
// surface_signature.h) with every invariant of the full check, and refuses unknown transactions,
// builds and conflicts with the store unchanged; --as-of reads the past without changing the
// store.
#include "db/history/revert.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "db/change_log.h"
#include "db/dem_store.h"
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
    auto report = RevertTransaction(*store_, tx, {.cascade = cascade});
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
  testing::ExpectSameFeatures(original, testing::SignatureOf(*store_), "after the revert");
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
  Revert(removed->tx);
  testing::ExpectSameFeatures(with_a, testing::SignatureOf(*store_), "after reverting the remove");

  const PolygonAddReport b = Update(a.first_feature_id, "b.geojson", Ngon(kCx, kCy, 4 * kCell, 9));
  const RevertReport r = Revert(b.tx);
  EXPECT_EQ(r.restored_features, std::vector<int64_t>{a.first_feature_id});
  testing::ExpectSameFeatures(with_a, testing::SignatureOf(*store_), "after reverting the update");
  // A revert is an edit like the others: reverting it redoes the update.
  Revert(r.transactions.at(0));
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
  testing::ExpectSameFeatures(original, testing::SignatureOf(*store_), "after the cascade");
}

// Reverts in reverse order need no --cascade: a later edit that was itself reverted left the
// feature as it was.
TEST_F(RevertTest, RevertsInReverseOrderAreNoConflict) {
  const testing::SurfaceSignature original = testing::SignatureOf(*store_);
  const PolygonAddReport a = Add("a.geojson", Ngon(kCx, kCy, 8 * kCell, 24));
  const PolygonAddReport b = Update(a.first_feature_id, "b.geojson", Ngon(kCx, kCy, 6 * kCell, 17));
  Revert(b.tx);
  const RevertReport r = Revert(a.tx);
  EXPECT_EQ(r.reverted, std::vector<int64_t>{a.tx});
  testing::ExpectSameFeatures(original, testing::SignatureOf(*store_), "after both reverts");
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
    testing::ExpectSameFeatures(after_a, testing::SignatureOf(*store_), "as of the first add");
  }
  EXPECT_EQ(Checksums(), before);

  auto future = BeginAsOf(*store_, *surface, b.tx + 100);
  EXPECT_EQ(future.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(future.status().message().find("in the future"), std::string::npos);
  EXPECT_EQ(Checksums(), before);
}

}  // namespace
}  // namespace tinbase
