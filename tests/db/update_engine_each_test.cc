// Loads feature by feature (`--each`): one transaction per feature, a failed one forgotten, and
// the mesh rows kept between transactions (db/mesh_cache.h) dropped whenever they may be stale.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/support/update_engine_checks.h"

namespace tinbase {
namespace {

using testing::BowTie;
using testing::kCell;
using testing::kCx;
using testing::kCy;
using testing::Ngon;
using testing::PointList;
using testing::UpdateEngineTest;
using testing::WritePolygons;

TEST_F(UpdateEngineTest, EachCommitsFeatureByFeature) {
  PolygonAddOptions o;
  o.surface = "terrain";
  o.mode = FeatureMode::kFill;
  o.each = true;
  o.strict = true;  // the second overhangs the surface
  o.file = WritePolygons(dir_, "two.geojson",
                         {{Ngon(kCx, kCy, 5 * kCell, 12)}, {Ngon(505374, kCy, 10 * kCell, 12)}});
  auto report = AddPolygons(*store_, o);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->features, 1);
  ASSERT_EQ(report->failures.size(), 1u);
  EXPECT_NE(report->failures[0].find("feature 1"), std::string::npos) << report->failures[0];
  testing::ExpectStoreIntact(*store_, /*full=*/true);
}

// `--each` hands the surface's features from one transaction to the next; a feature whose
// transaction fails (here the third) must not linger in them: the paint of the later, overlapping
// features is then checked against the stored features by the full check.
TEST_F(UpdateEngineTest, EachForgetsTheFeatureOfAFailedTransaction) {
  PolygonAddOptions o;
  o.surface = "terrain";
  o.mode = FeatureMode::kFill;
  o.tag_field = "unit";
  o.each = true;
  std::vector<std::vector<PointList>> rings;
  for (int k = 0; k < 5; ++k) rings.push_back({Ngon(kCx + k * 2 * kCell, kCy, 5 * kCell, 14)});
  o.file = WritePolygons(dir_, "five.geojson", rings);
  int edits = 0;
  ScopedUpdateEngineTestHooks hooks({[&edits](int step) {
    if (step == 1) ++edits;
    return edits == 3 && step == 1 ? Status::IOError("injected failure in the third edit")
                                   : Status::Ok();
  }});
  auto report = AddPolygons(*store_, o);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->features, 4);
  ASSERT_EQ(report->failures.size(), 1u);
  EXPECT_NE(report->failures[0].find("injected failure"), std::string::npos) << report->failures[0];
  EXPECT_EQ(Int("SELECT count(*) FROM features"), 4);
  EXPECT_EQ(Int("SELECT count(*) FROM features WHERE name = 'u2'"), 0);
  testing::ExpectStoreIntact(*store_, /*full=*/true);
}

// `--each` keeps the mesh rows the edits read from one transaction to the next
// (db/mesh_cache.h): every edit after the first begins from them, and with verify_mesh each
// compares every kept row with the store before using it.
TEST_F(UpdateEngineTest, EachKeepsTheMeshRowsBetweenTransactions) {
  std::vector<std::vector<PointList>> rings;
  for (int k = 0; k < 8; ++k) {
    const int column = k % 4, row = k / 4;  // a 4 x 2 array of polygons
    rings.push_back({Ngon(kCx + column * 3 * kCell, kCy + row * 3 * kCell, 4 * kCell, 13 + k)});
  }
  PolygonAddOptions o = EachFillOptions("eight.geojson", rings);
  auto report = AddVerifyingMesh(o);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->features, 8);
  EXPECT_TRUE(report->failures.empty());
  EXPECT_EQ(report->mesh_kept, 7);
  testing::ExpectStoreIntact(*store_, /*full=*/true);
}

// A load whose features together have at least a quarter as many ring points as the surface has
// triangles reaches much of it: its first edit reads every row in one scan, and the edits after
// it find every row and block held (and, with verify_mesh, equal to the store) instead of
// reading them one by one.
TEST_F(UpdateEngineTest, EachLoadOverMuchOfTheSurfaceReadsItOnce) {
  auto triangles = store_->db().QueryInt("SELECT count(*) FROM triangles");
  ASSERT_TRUE(triangles.ok());
  constexpr int kFeatures = 40;
  const int per_ring = static_cast<int>(*triangles / (4 * kFeatures)) + 10;  // that many points
  std::vector<std::vector<PointList>> rings;
  for (int k = 0; k < kFeatures; ++k) {
    const int column = k % 8 - 4, row = k / 8 - 2;  // an 8 x 5 array of polygons
    rings.push_back({Ngon(kCx + column * 7 * kCell, kCy + row * 7 * kCell, 3 * kCell, per_ring)});
  }
  PolygonAddOptions o = EachFillOptions("forty.geojson", rings);
  auto report = AddVerifyingMesh(o);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->features, kFeatures);
  EXPECT_TRUE(report->failures.empty());
  EXPECT_EQ(report->surface_reads, 1);
  EXPECT_EQ(report->mesh_kept, kFeatures - 1);
  testing::ExpectStoreIntact(*store_, /*full=*/true);

  // One feature on its own reads nothing whole.
  auto one = Add(WritePolygons(dir_, "one.geojson", {{Ngon(kCx, kCy, 2 * kCell, 12)}}), "fill");
  ASSERT_TRUE(one.ok()) << one.status().ToString();
  EXPECT_EQ(one->surface_reads, 0);
}

// A failure injected at each write step of the third of five edits: the kept rows go with the
// rollback (the failed edit may have forgotten only part of what it wrote), the fourth edit reads
// everything again, the fifth keeps the fourth's rows, and no kept row differs from the store.
TEST_F(UpdateEngineTest, EachDropsTheMeshRowsAfterAFailedTransaction) {
  for (int fail_at = 1; fail_at <= 7; ++fail_at) {
    SCOPED_TRACE("failure at write step " + std::to_string(fail_at));
    std::vector<std::vector<PointList>> rings;
    for (int k = 0; k < 5; ++k)
      rings.push_back(
          {Ngon(kCx + k * 2 * kCell, kCy + (fail_at - 4) * 6 * kCell, 5 * kCell, 14 + fail_at)});
    PolygonAddOptions o = EachFillOptions("five_" + std::to_string(fail_at) + ".geojson", rings);
    int edits = 0;
    auto report = AddVerifyingMesh(o, [&edits, fail_at](int step) {
      if (step == 0) ++edits;
      return edits == 3 && step == fail_at ? Status::IOError("injected failure in the third edit")
                                           : Status::Ok();
    });
    ASSERT_TRUE(report.ok()) << report.status().ToString();
    EXPECT_EQ(report->features, 4);
    ASSERT_EQ(report->failures.size(), 1u);
    EXPECT_NE(report->failures[0].find("injected failure"), std::string::npos)
        << report->failures[0];
    EXPECT_EQ(report->mesh_kept, 2);  // the second and the fifth edit
    testing::ExpectStoreIntact(*store_, /*full=*/true);
  }
}

// Another connection commits between two edits of a load feature by feature: a polygon edit (a
// new change number) before the third, a write without a `changes` row before the fifth (SQLite's
// data_version). Both times the next edit reads every row again.
TEST_F(UpdateEngineTest, EachDropsTheMeshRowsWhenAnotherWriterCommits) {
  auto first = Add(WritePolygons(dir_, "under.geojson", {{Ngon(kCx, kCy, 9 * kCell, 17)}}), "fill");
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  const int64_t under = first->first_feature_id;
  std::vector<std::vector<PointList>> rings;
  for (int k = 0; k < 5; ++k)
    rings.push_back({Ngon(kCx + (k - 2) * 3 * kCell, kCy + kCell, 4 * kCell, 15)});
  PolygonAddOptions o = EachFillOptions("over.geojson", rings);
  const std::string path = StoreTarget(dir_, "s.tinbase");
  int edits = 0;
  const FaultHook other_writer = [&](int step) -> Status {
    if (step != 0) return Status::Ok();
    ++edits;
    if (edits != 3 && edits != 5) return Status::Ok();
    TB_ASSIGN_OR_RETURN(auto other, Store::Open(path));
    if (edits == 3) return RemovePolygon(*other, under).status();
    // Flipped and back: SQLite does not rewrite a row whose bytes stay the same.
    TB_ASSIGN_OR_RETURN(auto tx, other->BeginWrite());
    for (int flip = 0; flip < 2; ++flip)
      TB_RETURN_IF_ERROR(other->db().Exec(
          "UPDATE triangles SET visible = 1 - visible WHERE id = (SELECT max(id) FROM triangles)"));
    return tx->Commit();
  };
  auto report = AddVerifyingMesh(o, other_writer);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->features, 5);
  EXPECT_TRUE(report->failures.empty());
  EXPECT_EQ(report->mesh_kept, 2);  // the second and the fourth edit
  EXPECT_EQ(Int("SELECT count(*) FROM features WHERE id = " + std::to_string(under)), 0);
  testing::ExpectStoreIntact(*store_, /*full=*/true);
}

TEST_F(UpdateEngineTest, EachReportsInvalidFeaturesAndAddsTheOthers) {
  // Feature 1 is a bow tie: without --each it fails the whole file; with --each it is reported,
  // naming the feature and ring, and features 0 and 2 are added.
  const PointList bow_tie = BowTie(3 * kCell);
  PolygonAddOptions o;
  o.surface = "terrain";
  o.mode = FeatureMode::kFill;
  o.tag = "unit";
  o.file = WritePolygons(dir_, "three.geojson",
                         {{Ngon(kCx - 12 * kCell, kCy, 4 * kCell, 12)},
                          {bow_tie},
                          {Ngon(kCx + 12 * kCell, kCy, 4 * kCell, 12)}});
  auto whole = AddPolygons(*store_, o);
  ASSERT_EQ(whole.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(Int("SELECT count(*) FROM features"), 0);
  o.each = true;
  auto report = AddPolygons(*store_, o);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->features, 2);
  ASSERT_EQ(report->failures.size(), 1u);
  EXPECT_NE(report->failures[0].find("feature 1, ring 0"), std::string::npos)
      << report->failures[0];
  EXPECT_EQ(Int("SELECT count(*) FROM features"), 2);
  testing::ExpectStoreIntact(*store_, /*full=*/true);
}

}  // namespace
}  // namespace tinbase
