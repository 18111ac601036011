// BuildTilePyramid on a stored surface in UTM: every level is crack-free between neighbours,
// layer.json's `available` is exactly the stored tiles, error bounds double per level up, hidden
// triangles leave holes, the water mask follows the water tag, and bad requests change nothing.
#include "db/tiles/tile_pyramid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/geometry/reproject.h"
#include "core/tiles/quantized_mesh.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tile_seams.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::TableChecksums;
using testing::TempDir;

class TilePyramidTest : public ::testing::Test {
 protected:
  void Create(const std::string& crs, Tin tin) {
    auto store = Store::Create(testing::StoreTarget(dir_, "s.tinbase"), crs);
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    SurfaceInfo spec;
    spec.name = "terrain";
    spec.method = "test";
    spec.tolerance = 2.0;
    auto info = SurfaceStore(*store_).Create(spec, tin);
    ASSERT_TRUE(info.ok()) << info.status().ToString();
    info_ = *info;
    ASSERT_TRUE((*tx)->Commit().ok());
  }

  static Tin Terrain(bool ring = false) {
    testing::RandomTinOptions options;
    options.points = 4000;
    options.ring = ring;
    return testing::RandomDelaunayTin(options);  // 10 km square in UTM 32N
  }

  std::map<TileKey, QuantizedMesh> Decoded() {
    std::map<TileKey, QuantizedMesh> out;
    TileStore tiles(store_->db());
    auto keys = tiles.Keys(info_.id);
    EXPECT_TRUE(keys.ok());
    for (const TileKey& key : *keys) {
      auto tile = tiles.Tile(info_.id, key);
      EXPECT_TRUE(tile.ok() && tile->has_value());
      auto mesh = DecodeQuantizedMesh((*tile)->first, key.ToString());
      EXPECT_TRUE(mesh.ok()) << mesh.status().ToString();
      out.emplace(key, std::move(*mesh));
    }
    return out;
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
  SurfaceInfo info_;
};

TEST_F(TilePyramidTest, EveryLevelIsCrackFreeAndLayerJsonIsExact) {
  Create("EPSG:32632", Terrain());
  TileBuildOptions options;
  options.max_zoom = 14;
  options.extensions.normals = true;
  options.extensions.metadata = true;
  auto report = BuildTilePyramid(*store_, info_, options);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  ASSERT_EQ(report->levels.size(), 15u);
  const auto tiles = Decoded();
  for (const auto& [key, mesh] : tiles) {
    EXPECT_TRUE(mesh.normals.has_value()) << key.ToString();
    EXPECT_EQ(mesh.metadata.has_value(), key.level % 10 == 0) << key.ToString();
  }
  const int pairs = testing::ExpectSeamsMatch(tiles);
  EXPECT_GT(pairs, 20);

  auto layer = LayerJson(*store_, info_);
  ASSERT_TRUE(layer.ok()) << layer.status().ToString();
  std::set<TileKey> listed;
  const auto& available = (*layer)["available"];
  ASSERT_EQ(available.size(), 15u);
  for (int level = 0; level < 15; ++level)
    for (const auto& r : available[level])
      for (int64_t y = r["startY"]; y <= r["endY"].get<int64_t>(); ++y)
        for (int64_t x = r["startX"]; x <= r["endX"].get<int64_t>(); ++x)
          EXPECT_TRUE(listed.insert({level, x, y}).second) << "listed twice";
  std::set<TileKey> stored;
  for (const auto& [key, mesh] : tiles) stored.insert(key);
  EXPECT_EQ(listed, stored);
  EXPECT_EQ((*layer)["maxzoom"], 14);
  EXPECT_EQ((*layer)["extensions"], nlohmann::json({"octvertexnormals", "metadata"}));
  const auto& errors = (*layer)["tinbase"]["geometricError"];
  ASSERT_EQ(errors.size(), 15u);
  EXPECT_EQ(errors[14], 0.0);
  EXPECT_EQ(errors[13], 2.0) << "the surface's tolerance, one level up";
  for (int level = 0; level + 1 < 14; ++level)
    EXPECT_EQ(errors[level].get<double>(), 2 * errors[level + 1].get<double>());
}

TEST_F(TilePyramidTest, HiddenTrianglesLeaveHoles) {
  Tin tin = Terrain();
  // Hide every triangle west of x = 605000.
  for (TinTriangle& t : tin.triangles) {
    double cx = 0;
    for (uint32_t v : t.v) cx += tin.vertices[v].x / 3;
    if (cx < 605000) t.visible = false;
  }
  Create("EPSG:32632", tin);
  TileBuildOptions options;
  options.max_zoom = 13;
  ASSERT_TRUE(BuildTilePyramid(*store_, info_, options).ok());
  // The longitude of x = 604300 (west of the hidden part's ragged edge by a few triangles) at its
  // most eastern, along the surface's south and north edges.
  auto utm = Crs::FromUserInput("EPSG:32632");
  auto wgs = Crs::FromUserInput("EPSG:4326");
  std::vector<TinVertex> probe = {{604300, 5100000, 0, VertexKind::kDem},
                                  {604300, 5110000, 0, VertexKind::kDem}};
  ASSERT_TRUE(ReprojectXy(*utm, *wgs, probe).ok());
  probe[0].x = std::max(probe[0].x, probe[1].x);
  for (const auto& [key, mesh] : Decoded()) {
    if (key.level != 13) continue;
    const TileRect r = RectOf(key);
    for (size_t i = 0; i < mesh.vertex_count(); ++i) {
      const double lon = r.west + mesh.u[i] / double(kQuantizedMax) * (r.east - r.west);
      EXPECT_GT(lon, probe[0].x) << key.ToString() << " has a vertex in the hidden part";
    }
  }
}

TEST_F(TilePyramidTest, WaterMaskMarksTheWaterTag) {
  Create("EPSG:32632", Terrain(/*ring=*/true));  // a 48-gon in the middle tagged "granite"
  TileBuildOptions options;
  options.max_zoom = 13;
  options.extensions.water_mask = true;
  options.water_tag = "granite";
  ASSERT_TRUE(BuildTilePyramid(*store_, info_, options).ok());
  int partial = 0;
  for (const auto& [key, mesh] : Decoded()) {
    ASSERT_TRUE(mesh.water_mask.has_value()) << key.ToString();
    const auto& m = *mesh.water_mask;
    if (m.size() == 65536) {
      const bool water = std::count(m.begin(), m.end(), 255) > 0;
      const bool land = std::count(m.begin(), m.end(), 0) > 0;
      EXPECT_TRUE(water && land) << key.ToString() << ": a full mask where one byte would do";
      ++partial;
    }
  }
  EXPECT_GT(partial, 0);
}

TEST_F(TilePyramidTest, BadRequestsAreRefusedAndChangeNothing) {
  Create("EPSG:32632", Terrain());
  TileBuildOptions good;
  good.max_zoom = 12;
  ASSERT_TRUE(BuildTilePyramid(*store_, info_, good).ok());
  const auto before = TableChecksums(testing::StoreTarget(dir_, "s.tinbase"));
  TileBuildOptions bad = good;
  bad.max_zoom = 25;
  EXPECT_NE(BuildTilePyramid(*store_, info_, bad).status().message().find("--max-zoom 25"),
            std::string::npos);
  bad = good;
  bad.extensions.water_mask = true;
  EXPECT_NE(BuildTilePyramid(*store_, info_, bad).status().message().find("--water-tag"),
            std::string::npos);
  bad.water_tag = "lake";
  EXPECT_NE(BuildTilePyramid(*store_, info_, bad).status().message().find("tag 'lake'"),
            std::string::npos);
  EXPECT_NE(ParseTileExtensions("octvertexnormals,shadows").status().message().find("'shadows'"),
            std::string::npos);
  EXPECT_EQ(TableChecksums(testing::StoreTarget(dir_, "s.tinbase")), before);
}

TEST_F(TilePyramidTest, StoreWithoutCrsIsRefused) {
  Create("", Terrain());
  auto report = BuildTilePyramid(*store_, info_, TileBuildOptions{});
  ASSERT_FALSE(report.ok());
  EXPECT_NE(report.status().message().find("no CRS"), std::string::npos)
      << report.status().message();
  EXPECT_EQ(LayerJson(*store_, info_).status().code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace tinbase
