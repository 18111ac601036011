// The local update engine through PolygonEditor (add, remove, update) on the Hamersley DEM:
// after every write the store passes the full check (all eight invariants), triangles outside
// the conflict region keep their ids and rows (except links across its outline), the changes
// log records the region, and a failure injected at any write step leaves the store unchanged.
#include "db/edit/update_engine.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/raster/gdal_raster.h"
#include "db/change_log.h"
#include "db/dem_store.h"
#include "db/edit/update_engine_test_hooks.h"
#include "db/integrity_check.h"
#include "db/point_locator.h"
#include "db/polygon_editor.h"
#include "db/surface_builder.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::StoreTarget;
using testing::TempDir;

// Centre of the Hamersley DEM (EPSG:28350), and its cell size.
constexpr double kCx = 539300, kCy = 7497340, kCell = 344.404386931320971;

// The whole-surface tests' map (SquareMap): kMapSide^2 square units of kMapUnitCells cells, on
// a second, coarser surface of the store (the first, "terrain", must keep its rows).
constexpr int kMapSide = 29;
constexpr double kMapUnitCells = 6;
// The map goes on a second, coarser surface of the store ("terrain" must keep its rows).
constexpr char kMapSurface[] = "coarse";
constexpr double kMapSurfaceTolerance = 25;

using testing::Ngon;
using testing::PointList;
using testing::WritePolygons;

struct Row {
  std::vector<int64_t> columns;  // v0, v1, v2, visible, tag, block (n0..n2 apart)
  std::vector<int64_t> links;
  bool operator==(const Row& o) const { return columns == o.columns; }
};

class UpdateEngineTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = Store::Create(StoreTarget(dir_, "s.tinbase"), "");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    DemStore dems(*store_);
    ASSERT_TRUE(dems.Import({DataPath("geology/hamersley/dtm_rp.tif")}, {}).ok());
    SurfaceBuildOptions o;
    o.surface = "terrain";
    o.greedy.tolerance = 5;
    auto built = BuildSurfaceFromDem(*store_, o);
    ASSERT_TRUE(built.ok()) << built.status().ToString();
  }

  std::map<int64_t, Row> Rows() {
    std::map<int64_t, Row> rows;
    auto prepared = store_->db().Prepare(
        "SELECT id, v0, v1, v2, visible, coalesce(tag, -1), block, coalesce(n0, -1), "
        "coalesce(n1, -1), coalesce(n2, -1) FROM triangles");
    EXPECT_TRUE(prepared.ok());
    Statement* stmt = prepared->get();
    while (*stmt->Step()) {
      Row r;
      for (int c = 1; c <= 6; ++c) r.columns.push_back(stmt->ColumnInt(c));
      for (int c = 7; c <= 9; ++c) r.links.push_back(stmt->ColumnInt(c));
      rows[stmt->ColumnInt(0)] = r;
    }
    return rows;
  }

  // Builds the map tests' surface (kMapSurface) beside "terrain"; returns its id.
  int64_t BuildMapSurface() {
    SurfaceBuildOptions o;
    o.surface = kMapSurface;
    o.greedy.tolerance = kMapSurfaceTolerance;
    auto built = BuildSurfaceFromDem(*store_, o);
    EXPECT_TRUE(built.ok()) << built.status().ToString();
    return Int(std::string("SELECT id FROM surfaces WHERE name = '") + kMapSurface + "'");
  }

  // id, x, y, z of the first `limit` vertices by id (all by default).
  std::vector<std::array<double, 4>> VertexRows(size_t limit = SIZE_MAX) {
    std::vector<std::array<double, 4>> rows;
    auto prepared = store_->db().Prepare("SELECT id, x, y, z FROM vertices ORDER BY id");
    EXPECT_TRUE(prepared.ok());
    Statement* stmt = prepared->get();
    while (rows.size() < limit && *stmt->Step())
      rows.push_back({static_cast<double>(stmt->ColumnInt(0)), stmt->ColumnDouble(1),
                      stmt->ColumnDouble(2), stmt->ColumnDouble(3)});
    return rows;
  }

  int64_t Int(const std::string& sql) {
    auto v = store_->db().QueryInt(sql);
    EXPECT_TRUE(v.ok()) << sql;
    return v.ok() ? *v : -1;
  }

  Result<PolygonAddReport> Add(const std::string& file, const std::string& mode,
                               std::optional<double> level = std::nullopt) {
    PolygonAddOptions o;
    o.surface = "terrain";
    o.file = file;
    auto parsed = ParseFeatureMode(mode);
    if (!parsed.ok()) return parsed.status();
    o.mode = *parsed;
    o.tag_field = mode == "fill" || mode == "replace" ? "unit" : "";
    o.level = level;
    o.strict = strict_;
    return AddPolygons(*store_, o);
  }

  // Adds and asserts: the full check passes, the triangles not removed keep their rows, and the
  // removed ones are exactly `removed` of the changes row.
  PolygonAddReport AddChecked(const std::string& file, const std::string& mode,
                              std::optional<double> level = std::nullopt) {
    const auto before = Rows();
    auto report = Add(file, mode, level);
    EXPECT_TRUE(report.ok()) << report.status().ToString();
    if (!report.ok()) return {};
    ExpectKept(before, *report);
    testing::ExpectStoreIntact(*store_, /*full=*/true);
    return *report;
  }

  // Removes feature `id` and asserts as AddChecked does.
  void RemoveChecked(int64_t id) {
    const auto before = Rows();
    auto removed = RemovePolygon(*store_, id);
    ASSERT_TRUE(removed.ok()) << removed.status().ToString();
    ExpectKept(before, *removed);
    testing::ExpectStoreIntact(*store_, /*full=*/true);
  }

  void ExpectKept(const std::map<int64_t, Row>& before, const PolygonAddReport& report) {
    const auto after = Rows();
    int64_t gone = 0, repainted = 0, created = 0;
    for (const auto& [id, row] : before) {
      auto it = after.find(id);
      if (it == after.end()) {
        ++gone;
        continue;
      }
      // Only visibility and tag may change (repaint), never the vertices or block.
      const bool same_shape =
          std::equal(row.columns.begin(), row.columns.begin() + 3, it->second.columns.begin()) &&
          row.columns[5] == it->second.columns[5];
      EXPECT_TRUE(same_shape) << "triangle " << id << " kept its id but changed its vertices";
      repainted += !(row == it->second);
    }
    for (const auto& [id, row] : after) created += !before.count(id);
    EXPECT_EQ(gone, report.removed);
    EXPECT_EQ(created, report.added);
    EXPECT_LT(gone, static_cast<int64_t>(before.size()) / 2) << "the region is not local";
    (void)repainted;
    auto changes = ChangesSince(*store_, report.tx - 1);
    ASSERT_TRUE(changes.ok());
    ASSERT_EQ(changes->size(), 1u);
    EXPECT_EQ((*changes)[0].removed, report.removed);
    EXPECT_EQ((*changes)[0].added, report.added);
  }

  // A feature-by-feature fill load of `rings` (written to `name`) tagged by "unit", with every
  // mesh row kept between its transactions compared with the store before use.
  PolygonAddOptions EachFillOptions(const std::string& name,
                                    const std::vector<std::vector<PointList>>& rings) {
    PolygonAddOptions o;
    o.surface = "terrain";
    o.mode = FeatureMode::kFill;
    o.tag_field = "unit";
    o.each = true;
    o.file = WritePolygons(dir_, name, rings);
    return o;
  }

  // AddPolygons(o) with every mesh row kept between transactions compared with the store before
  // use (verify_mesh) and `fault` called before each write step.
  Result<PolygonAddReport> AddVerifyingMesh(const PolygonAddOptions& o, FaultHook fault = nullptr) {
    ScopedUpdateEngineTestHooks hooks({std::move(fault), /*verify_mesh=*/true});
    return AddPolygons(*store_, o);
  }

  void Reopen() {
    auto store = Store::Open(StoreTarget(dir_, "s.tinbase"));
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
  }

  // Fault injection: runs AddPolygons(options) failing its Nth write step, N = 1, 2, ... until it
  // succeeds; every failed attempt must leave the store byte-for-byte as it was and intact.
  // Returns the report of the attempt that succeeded.
  PolygonAddReport FailEachWriteStepUntilItSucceeds(PolygonAddOptions options) {
    const std::string path = StoreTarget(dir_, "s.tinbase");
    for (int fail_at = 1; fail_at < 50; ++fail_at) {
      store_.reset();
      const auto before = testing::TableChecksums(path);
      Reopen();
      ScopedUpdateEngineTestHooks hooks({[fail_at](int step) {
        return step == fail_at
                   ? Status::IOError("injected failure at write step " + std::to_string(step))
                   : Status::Ok();
      }});
      auto report = AddPolygons(*store_, options);
      if (report.ok()) {
        EXPECT_GT(fail_at, 3);
        testing::ExpectStoreIntact(*store_, /*full=*/true);
        return *report;
      }
      EXPECT_EQ(report.status().code(), StatusCode::kIOError);
      testing::ExpectStoreIntact(*store_, /*full=*/true);
      store_.reset();
      EXPECT_EQ(testing::TableChecksums(path), before) << "fail at step " << fail_at;
      Reopen();
    }
    ADD_FAILURE() << "the insert never succeeded";
    return {};
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
  bool strict_ = false;  // Add: PolygonAddOptions::strict
};

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

// Luxembourg: a warped geographic DEM with nodata all around the country; R meets nodata
// triangles, which must stay hidden.
TEST(UpdateEngineNodataTest, PolygonsNearNodataKeepEveryInvariant) {
  TempDir dir;
  auto store = Store::Create(StoreTarget(dir, "lux.tinbase"), "");
  ASSERT_TRUE(store.ok());
  DemStore dems(**store);
  auto imported = dems.Import({DataPath("dem/elev.tif")}, {});
  ASSERT_TRUE(imported.ok()) << imported.status().ToString();
  SurfaceBuildOptions o;
  o.surface = "terrain";
  o.greedy.tolerance = 5;
  ASSERT_TRUE(BuildSurfaceFromDem(**store, o).ok());
  const GridGeometry& g = imported->dem.geometry;
  const double cx = (g.MinX() + g.MaxX()) / 2, cy = (g.MinY() + g.MaxY()) / 2;
  auto crs = (*store)->GetCrs();
  ASSERT_TRUE(crs.ok() && crs->has_value());
  auto epsg = (*crs)->Epsg();
  ASSERT_TRUE(epsg.has_value());
  for (int k = 0; k < 3; ++k) {
    PolygonAddOptions add;
    add.surface = "terrain";
    add.mode = k == 1 ? FeatureMode::kErase : FeatureMode::kFill;
    add.tag = "unit" + std::to_string(k);
    add.file = WritePolygons(
        dir, "p" + std::to_string(k) + ".geojson",
        {{Ngon(cx + (k - 1) * 5 * g.cell_x, cy, 10 * g.cell_x, 18 + k, 0.2 * k)}}, *epsg);
    auto added = AddPolygons(**store, add);
    ASSERT_TRUE(added.ok()) << added.status().ToString();
    testing::ExpectStoreIntact(**store, /*full=*/true);
  }
}

// A fill around a hole of nodata in a synthetic DEM: the blocks over the hole are painted
// triangle by triangle (their triangles stay hidden), the others on data whole.
TEST(UpdateEngineNodataTest, LargeFillAroundANodataHole) {
  TempDir dir;
  Grid grid;
  grid.geometry = GridGeometry{500000, 5200000, 10, -10, 120, 120};
  auto crs = Crs::FromUserInput("EPSG:32632");
  ASSERT_TRUE(crs.ok());
  grid.crs_wkt = crs->Wkt();
  grid.cells.resize(120 * 120);
  for (int64_t r = 0; r < 120; ++r)
    for (int64_t c = 0; c < 120; ++c)
      grid.cells[static_cast<size_t>(r * 120 + c)] =
          std::abs(r - 60) < 8 && std::abs(c - 55) < 6
              ? std::numeric_limits<float>::quiet_NaN()
              : static_cast<float>(300 + 20 * std::sin(c * 0.05) * std::cos(r * 0.04));
  ASSERT_TRUE(WriteGeoTiff(grid, dir.Path("hole.tif")).ok());
  auto store = Store::Create(StoreTarget(dir, "hole.tinbase"), "");
  ASSERT_TRUE(store.ok());
  DemStore dems(**store);
  ASSERT_TRUE(dems.Import({dir.Path("hole.tif")}, {}).ok());
  SurfaceBuildOptions o;
  o.surface = "terrain";
  o.greedy.tolerance = 0.5;
  ASSERT_TRUE(BuildSurfaceFromDem(**store, o).ok());
  const auto hidden = [&] {
    return *(*store)->db().QueryInt("SELECT count(*) FROM triangles WHERE visible = 0");
  };
  ASSERT_GT(hidden(), 0);
  PolygonAddOptions big;
  big.surface = "terrain";
  big.mode = FeatureMode::kFill;
  big.tag = "big";
  big.file = WritePolygons(dir, "big.geojson", {{Ngon(500600, 5199400, 500, 48)}}, 32632);
  auto added = AddPolygons(**store, big);
  ASSERT_TRUE(added.ok()) << added.status().ToString();
  testing::ExpectStoreIntact(**store, /*full=*/true);
  EXPECT_GT(hidden(), 0);
  EXPECT_GT(*(*store)->db().QueryInt("SELECT count(*) FROM triangles WHERE tag IS NOT NULL"),
            *(*store)->db().QueryInt("SELECT count(*) FROM triangles") / 4);
  auto removed = RemovePolygon(**store, added->first_feature_id);
  ASSERT_TRUE(removed.ok()) << removed.status().ToString();
  testing::ExpectStoreIntact(**store, /*full=*/true);
  EXPECT_EQ(*(*store)->db().QueryInt("SELECT count(*) FROM triangles WHERE tag IS NOT NULL"), 0);
}

// Regression (found by the kill -9 test): re-adding a ring whose segment an earlier ring crossed
// made CGAL reroute the new constraint through another vertex (CGAL#6602), leaving an edge
// stored unconstrained and not locally Delaunay.
TEST_F(UpdateEngineTest, RegressionReaddRingAlongEarlierCrossing) {
  std::vector<std::string> files;
  for (int k = 0; k < 6; ++k)
    files.push_back(WritePolygons(dir_, "p" + std::to_string(k) + ".geojson",
                                  {{Ngon(kCx + (k - 3) * 3 * kCell, kCy + (k % 2) * 4 * kCell,
                                         6 * kCell, 20 + k, 0.1 * k)}}));
  for (const std::string& file : files) AddChecked(file, "fill");
  AddChecked(files[0], "fill");
  AddChecked(files[1], "fill");
  AddChecked(files[2], "fill");  // failed the full check before the fix
}

// A ring vertex a hair (0.3 snap distances) beside an earlier ring's constrained edge lands on
// that edge, which is split there for its owner, instead of leaving a sliver beside it.
TEST_F(UpdateEngineTest, PointNearAnExistingConstraintSnapsOntoIt) {
  const PolygonAddReport a =
      AddChecked(WritePolygons(dir_, "a.geojson", {{Ngon(kCx, kCy, 10 * kCell, 12)}}), "fill");
  auto longest = store_->db().Prepare(
      "SELECT c.va, c.vb, p.x, p.y, q.x, q.y FROM constraints c JOIN vertices p ON p.id = c.va "
      "JOIN vertices q ON q.id = c.vb WHERE c.feature = ? "
      "ORDER BY (q.x - p.x) * (q.x - p.x) + (q.y - p.y) * (q.y - p.y) DESC LIMIT 1");
  ASSERT_TRUE(longest.ok());
  Statement* edge = longest->get();
  edge->Bind(1, a.first_feature_id);
  ASSERT_TRUE(*edge->Step());
  const int64_t va = edge->ColumnInt(0), vb = edge->ColumnInt(1);
  const double mx = (edge->ColumnDouble(2) + edge->ColumnDouble(4)) / 2;
  const double my = (edge->ColumnDouble(3) + edge->ColumnDouble(5)) / 2;
  edge->Reset();
  // Outward from a's centre, and along the edge.
  const double ox = (mx - kCx) / std::hypot(mx - kCx, my - kCy);
  const double oy = (my - kCy) / std::hypot(mx - kCx, my - kCy);
  const double px = mx + ox * 0.3 * kSnapCells * kCell, py = my + oy * 0.3 * kSnapCells * kCell;
  const PointList b = {{px, py},
                       {px + 4 * kCell * ox + 2 * kCell * oy, py + 4 * kCell * oy - 2 * kCell * ox},
                       {px + 4 * kCell * ox - 2 * kCell * oy, py + 4 * kCell * oy + 2 * kCell * ox},
                       {px, py}};
  const PolygonAddReport added = AddChecked(WritePolygons(dir_, "b.geojson", {{b}}), "fill");

  EXPECT_EQ(Int("SELECT count(*) FROM constraints WHERE va = " + std::to_string(va) +
                " AND vb = " + std::to_string(vb)),
            0)
      << "the edge the point snapped onto is still whole";
  std::ostringstream on_edge;
  on_edge.precision(17);
  on_edge << "SELECT id FROM vertices WHERE abs(x - " << mx << ") < 1e-6 AND abs(y - " << my
          << ") < 1e-6";
  const int64_t split = Int(on_edge.str());
  ASSERT_GT(split, 0) << "no vertex on the edge where b's vertex was";
  for (int64_t end : {va, vb}) {
    const std::string piece =
        "SELECT count(*) FROM constraints WHERE va = " + std::to_string(std::min(end, split)) +
        " AND vb = " + std::to_string(std::max(end, split));
    EXPECT_EQ(Int(piece + " AND feature = " + std::to_string(a.first_feature_id)), 1);
  }
  EXPECT_GE(Int("SELECT count(*) FROM constraints WHERE feature = " +
                std::to_string(added.first_feature_id) + " AND (va = " + std::to_string(split) +
                " OR vb = " + std::to_string(split) + ")"),
            2);
}

// A polygon whose every vertex lies a hair off an earlier ring's edges (both sides, random
// places along them): each snaps onto its edge; then the earlier ring goes and comes back (its
// new segments pass through those vertices), and both go, every step locally and checked.
TEST_F(UpdateEngineTest, RingOnAnotherRingsEdgesSnapsAndBothGoAgain) {
  const std::string a_file = WritePolygons(dir_, "a.geojson", {{Ngon(kCx, kCy, 10 * kCell, 12)}});
  for (int seed = 1; seed <= 3; ++seed) {
    const PolygonAddReport a = AddChecked(a_file, "fill");
    auto edges = store_->db().Prepare(
        "SELECT c.va, c.vb, p.x, p.y, q.x, q.y FROM constraints c JOIN vertices p ON p.id = c.va "
        "JOIN vertices q ON q.id = c.vb WHERE c.feature = ?");
    ASSERT_TRUE(edges.ok());
    (*edges)->Bind(1, a.first_feature_id);
    struct Near {
      double angle, x, y;
      int64_t va, vb;
    };
    std::vector<Near> points;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> along(0.25, 0.75), off(-0.5, 0.5);
    for (int k = 0; *(*edges)->Step(); ++k) {
      if (k % 2) continue;
      const double px = (*edges)->ColumnDouble(2), py = (*edges)->ColumnDouble(3);
      const double qx = (*edges)->ColumnDouble(4), qy = (*edges)->ColumnDouble(5);
      const double t = along(rng), len = std::hypot(qx - px, qy - py);
      const double o = off(rng) * kSnapCells * kCell;
      const double x = px + t * (qx - px) - o * (qy - py) / len;
      const double y = py + t * (qy - py) + o * (qx - px) / len;
      points.push_back(
          {std::atan2(y - kCy, x - kCx), x, y, (*edges)->ColumnInt(0), (*edges)->ColumnInt(1)});
    }
    (*edges)->Reset();
    ASSERT_GE(points.size(), 4u);
    std::sort(points.begin(), points.end(),
              [](const Near& l, const Near& r) { return l.angle < r.angle; });
    PointList ring;
    for (const Near& p : points) ring.push_back({p.x, p.y});
    ring.push_back(ring.front());
    const PolygonAddReport b =
        AddChecked(WritePolygons(dir_, "b" + std::to_string(seed) + ".geojson", {{ring}}), "erase");
    for (const Near& p : points) {
      EXPECT_EQ(Int("SELECT count(*) FROM constraints WHERE va = " + std::to_string(p.va) +
                    " AND vb = " + std::to_string(p.vb)),
                0)
          << "seed " << seed << ": an edge a vertex snapped onto is still whole";
    }
    RemoveChecked(a.first_feature_id);
    const PolygonAddReport again = AddChecked(a_file, "fill");  // now through b's vertices
    RemoveChecked(b.first_feature_id);
    RemoveChecked(again.first_feature_id);
    EXPECT_EQ(Int("SELECT count(*) FROM constraints"), 0);
    EXPECT_EQ(Int("SELECT count(*) FROM vertices WHERE kind IN ('ring', 'steiner')"), 0);
  }
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

// A self-intersecting ring (a figure of eight) of half-width d around the centre.
PointList BowTie(double d) {
  return {{kCx - d, kCy - d},
          {kCx + d, kCy + d},
          {kCx + d, kCy - d},
          {kCx - d, kCy + d},
          {kCx - d, kCy - d}};
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

// A map of side x side square units tiling most of the DEM (rings through a point every DEM
// cell, so their segments touch most triangles): loaded in one transaction, its conflict region
// is more than half of the surface, which the engine then re-triangulates whole
// (kMinWholeSurfaceRegion).
std::vector<std::vector<PointList>> SquareMap(int side, double cells_per_unit) {
  const double unit = cells_per_unit * kCell;
  const double x0 = kCx - side * unit / 2 + 0.37 * kCell, y0 = kCy - side * unit / 2 + 0.21 * kCell;
  const int steps = static_cast<int>(cells_per_unit);
  std::vector<std::vector<PointList>> map;
  for (int j = 0; j < side; ++j) {
    for (int i = 0; i < side; ++i) {
      const double x = x0 + i * unit, y = y0 + j * unit;
      PointList ring;
      for (int k = 0; k < steps; ++k) ring.push_back({x + unit * k / steps, y});
      for (int k = 0; k < steps; ++k) ring.push_back({x + unit, y + unit * k / steps});
      for (int k = 0; k < steps; ++k) ring.push_back({x + unit * (steps - k) / steps, y + unit});
      for (int k = 0; k < steps; ++k) ring.push_back({x, y + unit * (steps - k) / steps});
      ring.push_back(ring.front());
      map.push_back({ring});
    }
  }
  return map;
}

// Visibility and tag at points of a grid over the map, none on a ring: what paint a user sees,
// equal for any two triangulations of the same constraints whose paint is right.
std::vector<std::string> PaintSamples(Store& store) {
  auto surface = SurfaceStore(store).Find(kMapSurface);
  EXPECT_TRUE(surface.ok());
  std::vector<std::string> samples;
  if (!surface.ok()) return samples;
  PointLocator locator(store, *surface);
  const double half = kMapSide * kMapUnitCells * kCell / 2;
  for (double y = kCy - half; y < kCy + half; y += 2.9 * kCell) {
    for (double x = kCx - half; x < kCx + half; x += 3.1 * kCell) {
      auto at = locator.Locate(x, y);
      EXPECT_TRUE(at.ok()) << at.status().ToString();
      if (!at.ok()) continue;
      samples.push_back(std::to_string(at->visible) + ":" + at->tag.value_or("-"));
    }
  }
  return samples;
}

TEST_F(UpdateEngineTest, ManyFeaturesOverMostOfTheSurfaceReplaceItWhole) {
  const std::string file = WritePolygons(dir_, "map.geojson", SquareMap(kMapSide, kMapUnitCells));
  const std::string surface = std::to_string(BuildMapSurface());
  const int64_t triangles_before = Int("SELECT count(*) FROM triangles WHERE surface = " + surface);
  const int64_t last_id_before = Int("SELECT max(id) FROM triangles");
  const auto vertices_before = VertexRows();
  const auto terrain_before = Rows();  // both surfaces' rows
  // The same load feature by feature, every edit local, in a copy of the store.
  store_.reset();
  std::filesystem::copy_file(StoreTarget(dir_, "s.tinbase"), StoreTarget(dir_, "each.tinbase"));
  Reopen();

  PolygonAddOptions o;
  o.surface = kMapSurface;
  o.file = file;
  o.mode = FeatureMode::kFill;
  o.tag_field = "unit";
  auto report = AddPolygons(*store_, o);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  testing::ExpectStoreIntact(*store_, /*full=*/true);
  EXPECT_EQ(report->features, kMapSide * kMapSide);
  // The other surface's triangles are as they were.
  const auto after = Rows();
  for (const auto& [id, row] : terrain_before) {
    if (Int("SELECT count(*) FROM triangles WHERE surface = 1 AND id = " + std::to_string(id))) {
      EXPECT_TRUE(after.count(id) && after.at(id) == row) << "terrain triangle " << id;
    }
  }
  // Every triangle was replaced, by rows with ids above the old ones.
  EXPECT_EQ(report->removed, triangles_before);
  EXPECT_EQ(report->added, Int("SELECT count(*) FROM triangles WHERE surface = " + surface));
  EXPECT_EQ(Int("SELECT count(*) FROM triangles WHERE surface = " + surface +
                " AND id <= " + std::to_string(last_id_before)),
            0);
  // Vertices that stay keep their ids and rows (a fill moves none and drops none).
  EXPECT_EQ(VertexRows(vertices_before.size()), vertices_before);
  auto changes = ChangesSince(*store_, report->tx - 1);
  ASSERT_TRUE(changes.ok());
  ASSERT_EQ(changes->size(), 1u);
  EXPECT_EQ((*changes)[0].removed, report->removed);
  EXPECT_EQ((*changes)[0].added, report->added);
  EXPECT_EQ(Int("SELECT count(*) FROM features WHERE attributes LIKE '%\"unit\"%'"),
            kMapSide * kMapSide);
  const std::vector<std::string> whole = PaintSamples(*store_);

  auto each_store = Store::Open(StoreTarget(dir_, "each.tinbase"));
  ASSERT_TRUE(each_store.ok());
  o.each = true;
  auto each = AddPolygons(**each_store, o);
  ASSERT_TRUE(each.ok()) << each.status().ToString();
  EXPECT_TRUE(each->failures.empty());
  EXPECT_LT(each->removed, triangles_before * static_cast<int64_t>(kMapSide) * kMapSide / 4)
      << "feature by feature, each edit stays local";
  testing::ExpectStoreIntact(**each_store, /*full=*/true);
  EXPECT_EQ(PaintSamples(**each_store), whole);
}

// As FailureAtEveryWriteStepRollsBack, for the whole-surface path.
TEST_F(UpdateEngineTest, FailureAtEveryWriteStepOfAWholeSurfaceEditRollsBack) {
  const std::string file = WritePolygons(dir_, "map.geojson", SquareMap(kMapSide, kMapUnitCells));
  const std::string surface = std::to_string(BuildMapSurface());
  const int64_t triangles_before = Int("SELECT count(*) FROM triangles WHERE surface = " + surface);
  PolygonAddOptions o;
  o.surface = kMapSurface;
  o.file = file;
  o.mode = FeatureMode::kFill;
  o.tag_field = "unit";
  EXPECT_EQ(FailEachWriteStepUntilItSucceeds(o).removed, triangles_before)
      << "not the whole-surface path";
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
