// The `features.mode` column: every FeatureMode is written in its canonical spelling and read
// back as the same mode, and a row holding any other text is reported as Corruption naming the
// feature, not skipped or taken for a default.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "db/feature_store.h"
#include "db/surface_store.h"
#include "tests/support/grid_tin.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

class FeatureModeRowTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = Store::Create(testing::StoreTarget(dir_, "s.tinbase"), "EPSG:32632");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    SurfaceInfo spec;
    spec.name = "s";
    spec.kind = SurfaceKind::kDelaunay;
    spec.method = "test";
    auto info = SurfaceStore(*store_).Create(spec, testing::MakeGridTin(4, 4, 10));
    ASSERT_TRUE(info.ok()) << info.status().ToString();
    surface_ = *info;
    // One feature of every mode, in kFeatureModes order.
    for (FeatureMode mode : kFeatureModes) {
      EditorFeature f;
      f.label = FeatureModeName(mode);
      f.mode = mode;
      if (IsLineMode(mode))
        f.lines = {{{5, 5}, {35, 35}}};
      else
        f.polygons = {Polygon{{{5, 5}, {35, 5}, {35, 35}, {5, 35}}, {}}};
      if (mode == FeatureMode::kReplace) f.level = 12.5;
      ASSERT_TRUE(WriteFeature(*store_, surface_, 1, f).ok());
      ids_.push_back(f.id);
    }
    ASSERT_TRUE((*tx)->Commit().ok());
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
  SurfaceInfo surface_;
  std::vector<int64_t> ids_;
};

TEST_F(FeatureModeRowTest, EveryModeIsStoredInItsSpellingAndReadBack) {
  auto features = LoadFeatures(*store_, surface_);
  ASSERT_TRUE(features.ok()) << features.status().ToString();
  ASSERT_EQ(features->size(), kFeatureModes.size());
  for (size_t k = 0; k < kFeatureModes.size(); ++k) {
    const EditorFeature& f = (*features)[k];
    EXPECT_EQ(f.id, ids_[k]);
    EXPECT_EQ(f.mode, kFeatureModes[k]) << FeatureModeName(kFeatureModes[k]);
    EXPECT_EQ(f.lines.empty(), !IsLineMode(kFeatureModes[k]));
    auto stmt = store_->db().Cached("SELECT mode FROM features WHERE id = ?");
    ASSERT_TRUE(stmt.ok());
    (*stmt)->Bind(1, f.id);
    auto row = (*stmt)->Step();
    ASSERT_TRUE(row.ok() && *row);
    EXPECT_EQ((*stmt)->ColumnText(0), FeatureModeName(kFeatureModes[k]));
    (*stmt)->Reset();
  }
}

TEST_F(FeatureModeRowTest, AnUnknownModeInARowIsCorruptionNamingTheFeature) {
  // The schema's CHECK keeps such text out; a damaged or hand-edited file can still hold it.
  const int64_t bad = ids_[2];
  ASSERT_TRUE(store_->db().Exec("PRAGMA ignore_check_constraints = ON").ok());
  ASSERT_TRUE(store_->db()
                  .Exec("UPDATE features SET mode = 'paint' WHERE id = " + std::to_string(bad))
                  .ok());
  const std::string expected = "feature " + std::to_string(bad) +
                               ": unknown feature mode 'paint' (expected clip, erase, fill, "
                               "replace, breakline, softline or points)";
  auto all = LoadFeatures(*store_, surface_);
  ASSERT_FALSE(all.ok());
  EXPECT_EQ(all.status().code(), StatusCode::kCorruption);
  EXPECT_EQ(all.status().message(), expected);
  auto one = LoadFeature(*store_, surface_, bad);
  ASSERT_FALSE(one.ok());
  EXPECT_EQ(one.status().code(), StatusCode::kCorruption);
  EXPECT_EQ(one.status().message(), expected);
  // The other rows still read.
  EXPECT_TRUE(LoadFeature(*store_, surface_, ids_[0]).ok());
}

}  // namespace
}  // namespace tinbase
