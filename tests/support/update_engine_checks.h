// The fixture of the update engine's tests (update_engine_test, update_engine_each_test,
// update_engine_nodata_test, update_engine_snap_test, update_engine_whole_surface_test): a store
// on either backend (tests/support/store_target.h) with the Hamersley DEM and a surface
// "terrain" built on it, edits through PolygonEditor that assert the full check and the
// locality of every write (the triangles not removed keep their rows, the changes log records
// the region), and a failure-injection loop over the write steps.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "db/change_log.h"
#include "db/dem_store.h"
#include "db/edit/update_engine_test_hooks.h"
#include "db/integrity_check.h"
#include "db/polygon_editor.h"
#include "db/surface_builder.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase::testing {

// Centre of the Hamersley DEM (EPSG:28350), and its cell size.
inline constexpr double kCx = 539300, kCy = 7497340, kCell = 344.404386931320971;

// The whole-surface tests' map (SquareMap): kMapSide^2 square units of kMapUnitCells cells, on
// a second, coarser surface of the store (the first, "terrain", must keep its rows).
inline constexpr int kMapSide = 29;
inline constexpr double kMapUnitCells = 6;
// The map goes on a second, coarser surface of the store ("terrain" must keep its rows).
inline constexpr char kMapSurface[] = "coarse";
inline constexpr double kMapSurfaceTolerance = 25;

// A self-intersecting ring (a figure of eight) of half-width d around the centre.
inline PointList BowTie(double d) {
  return {{kCx - d, kCy - d},
          {kCx + d, kCy + d},
          {kCx + d, kCy - d},
          {kCx - d, kCy + d},
          {kCx - d, kCy - d}};
}

// A triangle row as the locality checks compare it.
struct TriangleRow {
  std::vector<int64_t> columns;  // v0, v1, v2, visible, tag, block (n0..n2 apart)
  std::vector<int64_t> links;
  bool operator==(const TriangleRow& o) const { return columns == o.columns; }
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

  std::map<int64_t, TriangleRow> Rows() {
    std::map<int64_t, TriangleRow> rows;
    auto prepared = store_->db().Prepare(
        "SELECT id, v0, v1, v2, visible, coalesce(tag, -1), block, coalesce(n0, -1), "
        "coalesce(n1, -1), coalesce(n2, -1) FROM triangles");
    EXPECT_TRUE(prepared.ok());
    Statement* stmt = prepared->get();
    while (*stmt->Step()) {
      TriangleRow r;
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

  void ExpectKept(const std::map<int64_t, TriangleRow>& before, const PolygonAddReport& report) {
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

}  // namespace tinbase::testing
