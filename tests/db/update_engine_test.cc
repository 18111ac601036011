// The local update engine through PolygonEditor (add, remove, update) on the Hamersley DEM:
// after every write the store passes the full check (all eight invariants), triangles outside
// the conflict region keep their ids and rows (except links across its outline), the changes
// log records the region, and a failure injected at any write step leaves the store unchanged.
// The fixture: tests/support/update_engine_checks.h; feature-by-feature loads, snapping, nodata
// and whole-surface edits have test files of their own (update_engine_*_test.cc).
#include "db/edit/update_engine.h"

#include <gtest/gtest.h>

#include <cmath>
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

TEST_F(UpdateEngineTest, AddIsLocalAndKeepsEveryInvariant) {
  const std::string file = WritePolygons(
      dir_, "a.geojson", {{Ngon(kCx, kCy, 12 * kCell, 40), Ngon(kCx, kCy, 4 * kCell, 12, 0.3)}});
  const PolygonAddReport r = AddChecked(file, "fill");
  EXPECT_EQ(r.features, 1);
  EXPECT_GT(r.removed, 0);
  // Constraints carry their feature; the hole's inside is untagged, the ring's inside tagged.
  EXPECT_EQ(Int("SELECT count(*) FROM constraints WHERE feature IS NULL"), 0);
  EXPECT_GE(
      Int("SELECT count(*) FROM constraints WHERE feature = " + std::to_string(r.first_feature_id)),
      52);
  EXPECT_GT(Int("SELECT count(*) FROM triangles WHERE tag IS NOT NULL"), 0);
}

TEST_F(UpdateEngineTest, OverlappingCrossingTouchingFeatures) {
  const PointList a = Ngon(kCx, kCy, 10 * kCell, 30);
  // b crosses a's ring many times; c shares a's vertices exactly on one side (touching);
  // d is a clip polygon around both.
  AddChecked(WritePolygons(dir_, "a.geojson", {{a}}), "fill");
  AddChecked(WritePolygons(dir_, "b.geojson", {{Ngon(kCx + 7 * kCell, kCy, 9 * kCell, 23, 0.7)}}),
             "fill");
  PointList c = {a[0], a[1], a[2], a[3]};
  c.push_back({a[3].first + 8 * kCell, a[3].second + 8 * kCell});
  c.push_back(a[0]);
  std::reverse(c.begin(), c.end());  // a's edges traversed the other way
  AddChecked(WritePolygons(dir_, "c.geojson", {{c}}), "erase");
  AddChecked(WritePolygons(dir_, "d.geojson", {{Ngon(kCx, kCy, 30 * kCell, 16)}}), "clip");
  // Shared edges have one row per feature.
  EXPECT_GT(Int("SELECT count(*) FROM (SELECT va, vb FROM constraints GROUP BY va, vb "
                "HAVING count(*) > 1) AS shared"),
            0);
}

// A ring that runs along constraints already stored (a map's shared boundaries) changes no
// triangle: its segments only gain an owner, and paint follows the new feature.
TEST_F(UpdateEngineTest, RingAlongStoredConstraintsRetriangulatesNothing) {
  PointList ring = Ngon(kCx, kCy, 10 * kCell, 30);
  const PolygonAddReport a = AddChecked(WritePolygons(dir_, "a.geojson", {{ring}}), "fill");
  const std::string count_a =
      "SELECT count(*) FROM constraints WHERE feature = " + std::to_string(a.first_feature_id);
  const int64_t edges = Int(count_a);
  ASSERT_GE(edges, 30);
  std::reverse(ring.begin(), ring.end());  // the same edges, traversed the other way
  const int64_t visible = Int("SELECT count(*) FROM triangles WHERE visible = 1");
  const PolygonAddReport b = AddChecked(WritePolygons(dir_, "b.geojson", {{ring}}), "erase");
  EXPECT_EQ(b.removed, 0);
  EXPECT_EQ(b.added, 0);
  EXPECT_EQ(
      Int("SELECT count(*) FROM constraints WHERE feature = " + std::to_string(b.first_feature_id)),
      edges);
  EXPECT_EQ(Int(count_a), edges);
  EXPECT_LT(Int("SELECT count(*) FROM triangles WHERE visible = 1"), visible);
  // Removing either feature leaves the other's ring whole.
  RemoveChecked(a.first_feature_id);
  EXPECT_EQ(Int("SELECT count(*) FROM constraints"), edges);
}

// The same ring again, with a polygon crossing it in the same edit: the stored edges the new
// ring runs along are split at the crossings, and the new ring's rows follow them piece by piece
// as the old ring's do.
TEST_F(UpdateEngineTest, RingAlongStoredConstraintsFollowsTheirSplits) {
  const PointList ring = Ngon(kCx, kCy, 10 * kCell, 30);
  const PolygonAddReport a = AddChecked(WritePolygons(dir_, "a.geojson", {{ring}}), "fill");
  const auto rows_of = [this](int64_t feature) {
    return Int("SELECT count(*) FROM constraints WHERE feature = " + std::to_string(feature));
  };
  const int64_t edges = rows_of(a.first_feature_id);
  const PolygonAddReport bc = AddChecked(
      WritePolygons(dir_, "bc.geojson", {{ring}, {Ngon(kCx + 7 * kCell, kCy, 9 * kCell, 23, 0.7)}}),
      "fill");
  EXPECT_EQ(bc.features, 2);
  EXPECT_GT(rows_of(a.first_feature_id), edges) << "the crossing polygon split no edge of the ring";
  EXPECT_EQ(rows_of(bc.first_feature_id), rows_of(a.first_feature_id));
  // Every piece of the ring has both owners.
  EXPECT_EQ(Int("SELECT count(*) FROM (SELECT va, vb FROM constraints WHERE feature IN (" +
                std::to_string(a.first_feature_id) + ", " + std::to_string(bc.first_feature_id) +
                ") GROUP BY va, vb HAVING count(*) = 2) AS shared"),
            rows_of(a.first_feature_id));
}

TEST_F(UpdateEngineTest, RemoveAndUpdateAreLocalAndRestoreTheSurface) {
  const PolygonAddReport a =
      AddChecked(WritePolygons(dir_, "a.geojson", {{Ngon(kCx, kCy, 10 * kCell, 30)}}), "fill");
  const PolygonAddReport b = AddChecked(
      WritePolygons(dir_, "b.geojson", {{Ngon(kCx + 6 * kCell, kCy, 8 * kCell, 21, 0.4)}}),
      "erase");
  ASSERT_GT(a.first_feature_id, 0);
  ASSERT_GT(b.first_feature_id, 0);

  RemoveChecked(a.first_feature_id);
  EXPECT_EQ(
      Int("SELECT count(*) FROM constraints WHERE feature = " + std::to_string(a.first_feature_id)),
      0);
  EXPECT_EQ(Int("SELECT count(*) FROM features WHERE id = " + std::to_string(a.first_feature_id)),
            0);

  PolygonAddOptions update;
  update.file = WritePolygons(dir_, "b2.geojson", {{Ngon(kCx - 5 * kCell, kCy, 6 * kCell, 17)}});
  const auto before = Rows();
  auto updated = UpdatePolygon(*store_, b.first_feature_id, update);
  ASSERT_TRUE(updated.ok()) << updated.status().ToString();
  ExpectKept(before, *updated);
  testing::ExpectStoreIntact(*store_, /*full=*/true);
  EXPECT_EQ(Int("SELECT count(*) FROM features WHERE mode = 'erase' AND id = " +
                std::to_string(updated->first_feature_id)),
            1);

  auto last = RemovePolygon(*store_, updated->first_feature_id);
  ASSERT_TRUE(last.ok()) << last.status().ToString();
  testing::ExpectStoreIntact(*store_, /*full=*/true);
  // Nothing of the features is left: no constraint, no ring or crossing vertex.
  EXPECT_EQ(Int("SELECT count(*) FROM constraints"), 0);
  EXPECT_EQ(Int("SELECT count(*) FROM vertices WHERE kind IN ('ring', 'steiner')"), 0);
  EXPECT_EQ(Int("SELECT count(*) FROM triangles WHERE tag IS NOT NULL"), 0);

  auto missing = RemovePolygon(*store_, 999);
  EXPECT_EQ(missing.status().code(), StatusCode::kNotFound);
}

// A fill far larger than the surface's blocks: most of its blocks are repainted whole, from the
// paint at their centre (db/update_engine FindPaintArea), over earlier features it covers
// (a later fill wins, an erase still hides) and when those features go again.
TEST_F(UpdateEngineTest, LargeFillRepaintsWholeBlocksOverOtherFeatures) {
  const auto add = [&](const std::string& name, const PointList& ring, const std::string& mode,
                       const std::string& tag) {
    PolygonAddOptions o;
    o.surface = "terrain";
    o.file = WritePolygons(dir_, name, {{ring}});
    o.mode = *ParseFeatureMode(mode);
    o.tag = tag;
    const auto before = Rows();
    auto report = AddPolygons(*store_, o);
    EXPECT_TRUE(report.ok()) << report.status().ToString();
    if (!report.ok()) return int64_t{0};
    ExpectKept(before, *report);
    testing::ExpectStoreIntact(*store_, /*full=*/true);
    return report->first_feature_id;
  };
  const auto tagged = [&](const std::string& tag) {
    return Int("SELECT count(*) FROM triangles t JOIN tags g ON g.id = t.tag WHERE g.value = '" +
               tag + "'");
  };
  const int64_t all = Int("SELECT count(*) FROM triangles");
  const int64_t inner = add("inner.geojson", Ngon(kCx, kCy, 10 * kCell, 30), "fill", "inner");
  add("hole.geojson", Ngon(kCx + 3 * kCell, kCy, 4 * kCell, 14, 0.3), "erase", "");
  const int64_t outer = add("outer.geojson", Ngon(kCx, kCy, 60 * kCell, 90, 0.2), "fill", "outer");
  EXPECT_EQ(tagged("inner"), 0) << "the later fill covers the earlier one everywhere";
  EXPECT_GT(tagged("outer"), all / 4);
  EXPECT_GT(Int("SELECT count(*) FROM triangles WHERE visible = 0"), 0);

  const int64_t outer_before = tagged("outer");
  RemoveChecked(inner);  // under the outer fill: no paint changes but along its ring's region
  EXPECT_GT(tagged("outer"), outer_before - outer_before / 10);
  EXPECT_GT(Int("SELECT count(*) FROM triangles WHERE visible = 0"), 0) << "the erase stays";
  RemoveChecked(outer);
  EXPECT_EQ(tagged("outer"), 0);
  EXPECT_EQ(Int("SELECT count(*) FROM triangles WHERE tag IS NOT NULL"), 0);
}

TEST_F(UpdateEngineTest, ReplaceFlattensAndRemovingItRestoresTheTolerance) {
  const PolygonAddReport r = AddChecked(
      WritePolygons(dir_, "lake.geojson", {{Ngon(kCx, kCy, 9 * kCell, 25)}}), "replace", 400.0);
  EXPECT_GT(Int("SELECT count(*) FROM vertices WHERE z = 400"), 25);
  auto removed = RemovePolygon(*store_, r.first_feature_id);
  ASSERT_TRUE(removed.ok()) << removed.status().ToString();
  testing::ExpectStoreIntact(*store_, /*full=*/true);
}

TEST_F(UpdateEngineTest, BreaklinesCrossRingsAndGoAgain) {
  AddChecked(WritePolygons(dir_, "a.geojson", {{Ngon(kCx, kCy, 8 * kCell, 24)}}), "fill");
  const std::string line = dir_.Path("line.geojson");
  std::ofstream(line) << std::setprecision(17)
                      << R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": )"
                      << R"({"name": "urn:ogc:def:crs:EPSG::28350"}}, "features": [{"type": )"
                      << R"("Feature", "properties": {}, "geometry": {"type": "LineString", )"
                      << R"("coordinates": [[)" << kCx - 12 * kCell << "," << kCy - 3 * kCell
                      << "],[" << kCx + 0.5 * kCell << "," << kCy + 0.3 * kCell << "],["
                      << kCx + 12 * kCell << "," << kCy + 5 * kCell << "]]}}]}";
  const PolygonAddReport r = AddChecked(line, "breakline");
  // The line crosses the ring twice: two crossing vertices, shared by both features' rows.
  EXPECT_GE(Int("SELECT count(*) FROM vertices WHERE kind = 'steiner'"), 2);
  auto removed = RemovePolygon(*store_, r.first_feature_id);
  ASSERT_TRUE(removed.ok()) << removed.status().ToString();
  testing::ExpectStoreIntact(*store_, /*full=*/true);
}

TEST_F(UpdateEngineTest, RingsOnTheDomainBoundary) {
  // The surface spans the DEM's cell centres; this square shares its north-west corner and runs
  // along its west and north edges, so R reaches the domain boundary and new points split it.
  const double x0 = 505374.706305430852808 + kCell / 2, y0 = 7532468.693823986686766 - kCell / 2;
  const PointList corner = {{x0, y0},
                            {x0, y0 - 6.3 * kCell},
                            {x0 + 5.7 * kCell, y0 - 6.3 * kCell},
                            {x0 + 5.7 * kCell, y0},
                            {x0, y0}};
  const PolygonAddReport r = AddChecked(WritePolygons(dir_, "corner.geojson", {{corner}}), "erase");
  auto removed = RemovePolygon(*store_, r.first_feature_id);
  ASSERT_TRUE(removed.ok()) << removed.status().ToString();
  testing::ExpectStoreIntact(*store_, /*full=*/true);
}

TEST_F(UpdateEngineTest, BadInputLeavesTheStoreUnchanged) {
  store_.reset();
  const auto before = testing::TableChecksums(StoreTarget(dir_, "s.tinbase"));
  auto store = Store::Open(StoreTarget(dir_, "s.tinbase"));
  ASSERT_TRUE(store.ok());
  store_ = std::move(*store);
  // Partly outside the DEM: refused with --strict (clipping: tests/db/edit/overhang_clip_test.cc).
  strict_ = true;
  auto outside =
      Add(WritePolygons(dir_, "out.geojson", {{Ngon(505374, kCy, 10 * kCell, 12)}}), "fill");
  EXPECT_EQ(outside.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(outside.status().message().find("ring 0"), std::string::npos)
      << outside.status().message();
  // Inside the DEM but outside the surface (which spans the cell centres): the outer half cell.
  const double west = 505374.706305430852808 + 0.2 * kCell;
  auto off_surface =
      Add(WritePolygons(dir_, "o.geojson",
                        {{{{west, kCy}, {kCx, kCy - 3 * kCell}, {kCx, kCy}, {west, kCy}}}}),
          "fill");
  EXPECT_EQ(off_surface.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(off_surface.status().message().find("ring 0, vertex 0"), std::string::npos)
      << off_surface.status().message();
  EXPECT_NE(off_surface.status().message().find("lies outside surface 'terrain'"),
            std::string::npos)
      << off_surface.status().message();
  auto mode = Add(WritePolygons(dir_, "m.geojson", {{Ngon(kCx, kCy, 3 * kCell, 5)}}), "paint");
  EXPECT_EQ(mode.status().code(), StatusCode::kInvalidArgument);
  std::ofstream(dir_.Path("empty.geojson")) << R"({"type": "FeatureCollection", "features": []})";
  auto empty = Add(dir_.Path("empty.geojson"), "fill");
  EXPECT_FALSE(empty.ok());
  store_.reset();
  EXPECT_EQ(testing::TableChecksums(StoreTarget(dir_, "s.tinbase")), before);
}

TEST_F(UpdateEngineTest, RepairTurnsABowTieIntoTwoPolygons) {
  const PointList bow_tie = BowTie(5 * kCell);
  PolygonAddOptions o;
  o.surface = "terrain";
  o.mode = FeatureMode::kFill;
  o.tag = "bow";
  o.file = WritePolygons(dir_, "bow.geojson", {{bow_tie}});
  auto rejected = AddPolygons(*store_, o);
  ASSERT_EQ(rejected.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(rejected.status().message().find("ring 0"), std::string::npos)
      << rejected.status().message();
  o.repair = true;
  auto repaired = AddPolygons(*store_, o);
  ASSERT_TRUE(repaired.ok()) << repaired.status().ToString();
  testing::ExpectStoreIntact(*store_, /*full=*/true);
  EXPECT_GT(Int("SELECT count(*) FROM triangles t JOIN tags g ON g.id = t.tag "
                "WHERE g.value = 'bow'"),
            0);
}

// Fault injection: fail the Nth write step, N = 1, 2, ... until the insert succeeds; every failed
// attempt leaves the store byte-for-byte as it was and intact.
TEST_F(UpdateEngineTest, FailureAtEveryWriteStepRollsBack) {
  AddChecked(WritePolygons(dir_, "a.geojson", {{Ngon(kCx, kCy, 8 * kCell, 20)}}), "fill");
  PolygonAddOptions o;
  o.surface = "terrain";
  o.file = WritePolygons(dir_, "b.geojson", {{Ngon(kCx + 5 * kCell, kCy, 7 * kCell, 19, 0.5)}});
  o.mode = FeatureMode::kErase;
  FailEachWriteStepUntilItSucceeds(o);
}

}  // namespace
}  // namespace tinbase
