// Windows of a tile pyramid (db/tiles/tile_window.h): a build's tiles do not depend on how many
// windows it reads the surface in, one tile made on demand is the stored tile, and an update
// after an edit across several tiles and levels reads only its window and equals a fresh build
// byte for byte, rewriting only the tiles that meet the change; an edit that moves the height
// range rebuilds everything, and equals a fresh build too.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "db/change_log.h"
#include "db/feature_store.h"
#include "db/mesh/mesh_tables.h"
#include "db/tiles/tile_pyramid.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::TempDir;
using Tiles = std::map<TileKey, std::pair<std::vector<uint8_t>, int64_t>>;

class TileUpdateTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = Store::Create(testing::StoreTarget(dir_, "s.tinbase"), "EPSG:32632");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    SurfaceInfo spec;
    spec.name = "terrain";
    spec.method = "test";
    spec.tolerance = 2.0;
    testing::RandomTinOptions random;
    random.points = 4000;
    random.ring = true;  // a 48-gon in the middle tagged "granite"
    auto info = SurfaceStore(*store_).Create(spec, testing::RandomDelaunayTin(random));
    ASSERT_TRUE(info.ok()) << info.status().ToString();
    info_ = *info;
    ASSERT_TRUE((*tx)->Commit().ok());
    options_.max_zoom = 14;
    options_.extensions.normals = true;
    options_.extensions.metadata = true;
    options_.extensions.water_mask = true;
    options_.water_tag = "granite";
  }

  Tiles Stored() {
    Tiles out;
    TileStore tiles(store_->db());
    auto keys = tiles.Keys(info_.id);
    EXPECT_TRUE(keys.ok());
    for (const TileKey& key : *keys) {
      auto tile = tiles.Tile(info_.id, key);
      EXPECT_TRUE(tile.ok() && tile->has_value());
      out.emplace(key, **tile);
    }
    return out;
  }

  static std::map<TileKey, std::vector<uint8_t>> BytesOf(const Tiles& tiles) {
    std::map<TileKey, std::vector<uint8_t>> out;
    for (const auto& [key, tile] : tiles) out.emplace(key, tile.first);
    return out;
  }

  // "" when `a` and `b` hold the same tiles with the same bytes, else the first keys that differ.
  static std::string Differences(const std::map<TileKey, std::vector<uint8_t>>& a,
                                 const std::map<TileKey, std::vector<uint8_t>>& b) {
    std::string out;
    int listed = 0;
    std::set<TileKey> keys;
    for (const auto& [key, bytes] : a) keys.insert(key);
    for (const auto& [key, bytes] : b) keys.insert(key);
    for (const TileKey& key : keys) {
      const auto ia = a.find(key);
      const auto ib = b.find(key);
      if (ia != a.end() && ib != b.end() && ia->second == ib->second) continue;
      if (listed++ < 8)
        out += key.ToString() +
               (ia == a.end()   ? " (only 2nd)"
                : ib == b.end() ? " (only 1st)"
                                : "") +
               " ";
    }
    return listed == 0 ? "" : std::to_string(listed) + " differ: " + out;
  }

  // One transaction that changes the surface's rows through `edit` and logs a change whose
  // region is the box of every triangle holding a changed vertex or repainted (as an edit does).
  void Edit(const std::function<std::vector<int64_t>(MeshTables&, LoadedSurface&)>& edit) {
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    auto loaded = SurfaceStore(*store_).Load(info_);
    ASSERT_TRUE(loaded.ok());
    MeshTables tables(store_->db(), info_);
    const std::vector<int64_t> touched_triangles = edit(tables, *loaded);
    ASSERT_FALSE(touched_triangles.empty());
    Change change;
    change.surface = info_.id;
    change.action = "test edit";
    Box box;
    for (const int64_t id : touched_triangles) {
      const size_t t = IndexOf(loaded->triangle_ids, id);
      for (const uint32_t v : loaded->tin.triangles[t].v)
        box.Add(Point2{loaded->tin.vertices[v].x, loaded->tin.vertices[v].y});
    }
    change.min_x = box.min_x, change.min_y = box.min_y;
    change.max_x = box.max_x, change.max_y = box.max_y;
    ASSERT_TRUE(AppendChange(*store_, change).ok());
    ASSERT_TRUE((*tx)->Commit().ok());
  }

  static size_t IndexOf(const std::vector<int64_t>& ids, int64_t id) {
    return static_cast<size_t>(std::lower_bound(ids.begin(), ids.end(), id) - ids.begin());
  }

  // Sets the z of the vertices with `pick` to `z` and returns the triangles around them.
  static std::vector<int64_t> MoveVertices(MeshTables& tables, LoadedSurface& s,
                                           const std::function<bool(size_t)>& pick, double z) {
    std::vector<VertexZ> moved;
    std::set<uint32_t> picked;
    for (size_t v = 0; v < s.tin.vertices.size(); ++v)
      if (pick(v)) {
        VertexRow row = s.tin.vertices[v];
        row.z = z;
        moved.push_back({s.vertex_ids[v], row});
        picked.insert(static_cast<uint32_t>(v));
      }
    EXPECT_TRUE(tables.SetVertexZ(moved).ok());
    std::vector<int64_t> around;
    for (size_t t = 0; t < s.tin.triangles.size(); ++t)
      for (const uint32_t v : s.tin.triangles[t].v)
        if (picked.count(v) > 0) {
          around.push_back(s.triangle_ids[t]);
          break;
        }
    return around;
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
  SurfaceInfo info_;
  TileBuildOptions options_;
};

TEST_F(TileUpdateTest, TheWindowSizeDoesNotChangeTheTiles) {
  options_.window_triangles = int64_t{1} << 40;  // the whole surface in one window
  ASSERT_TRUE(BuildTilePyramid(*store_, info_, options_).ok());
  const auto whole = BytesOf(Stored());
  ASSERT_GT(whole.size(), 40u);
  options_.window_triangles = 1000;  // a few finest tiles a window
  ASSERT_TRUE(BuildTilePyramid(*store_, info_, options_).ok());
  EXPECT_EQ(Differences(BytesOf(Stored()), whole), "");
}

TEST_F(TileUpdateTest, ATileMadeOnDemandIsTheStoredTile) {
  ASSERT_TRUE(BuildTilePyramid(*store_, info_, options_).ok());
  std::set<int> levels, sampled;
  for (const auto& [key, bytes] : BytesOf(Stored())) {
    levels.insert(key.level);
    if (key.x % 3 != 0 && key.level > 9) continue;  // a sample of the finer levels
    auto made = MakeTile(*store_, info_, key);
    ASSERT_TRUE(made.ok()) << key.ToString() << ": " << made.status().ToString();
    EXPECT_TRUE(*made == bytes) << key.ToString();
    sampled.insert(key.level);
  }
  EXPECT_EQ(sampled, levels);
  EXPECT_GE(levels.size(), 8u);
  EXPECT_EQ(MakeTile(*store_, info_, {15, 0, 0}).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(MakeTile(*store_, info_, {14, 0, 0}).status().code(), StatusCode::kNotFound);
}

TEST_F(TileUpdateTest, AnEditAcrossSeveralTilesAndLevelsEqualsAFreshBuild) {
  ASSERT_TRUE(BuildTilePyramid(*store_, info_, options_).ok());
  const Tiles before = Stored();
  auto pyramid = TileStore(store_->db()).Pyramid(info_.id);
  ASSERT_TRUE(pyramid.ok() && pyramid->has_value());
  const double middle = ((*pyramid)->min_height + (*pyramid)->max_height) / 2;
  // A 3 km x 2 km box in the south-west: its vertices flattened to the middle height (the two
  // that hold the height range kept), and the triangles whose centroid it holds hidden.
  const auto in_box = [](double x, double y) {
    return x > 601000 && x < 604000 && y > 5101000 && y < 5103000;
  };
  Edit([&](MeshTables& tables, LoadedSurface& s) {
    std::vector<int64_t> touched = MoveVertices(
        tables, s,
        [&](size_t v) {
          const int64_t id = s.vertex_ids[v];
          return in_box(s.tin.vertices[v].x, s.tin.vertices[v].y) && id != (*pyramid)->min_vertex &&
                 id != (*pyramid)->max_vertex;
        },
        middle);
    std::vector<int64_t> hidden;
    for (size_t t = 0; t < s.tin.triangles.size(); ++t) {
      double cx = 0, cy = 0;
      for (const uint32_t v : s.tin.triangles[t].v)
        cx += s.tin.vertices[v].x / 3, cy += s.tin.vertices[v].y / 3;
      if (in_box(cx, cy) && cx < 602500) hidden.push_back(s.triangle_ids[t]);
    }
    EXPECT_TRUE(tables.RepaintIds(false, std::nullopt, hidden).ok());
    touched.insert(touched.end(), hidden.begin(), hidden.end());
    return touched;
  });
  auto report = UpdateTilePyramid(*store_, info_);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_FALSE(report->full_rebuild);
  EXPECT_EQ(report->changes, 1);
  const Tiles after = Stored();
  std::set<int> levels, rewritten_levels;
  int64_t finest_rewritten = 0, untouched = 0;
  for (const auto& [key, tile] : after) {
    levels.insert(key.level);
    auto old = before.find(key);
    if (old != before.end() && old->second.second == tile.second) {
      EXPECT_EQ(old->second.first, tile.first) << key.ToString();
      ++untouched;
      continue;
    }
    rewritten_levels.insert(key.level);
    if (key.level == 14) ++finest_rewritten;
  }
  EXPECT_EQ(untouched + report->tiles_rewritten, static_cast<int64_t>(after.size()));
  EXPECT_GE(finest_rewritten, 6) << "the box spans several finest tiles";
  EXPECT_EQ(rewritten_levels, levels) << "and reaches every level";
  EXPECT_GE(levels.size(), 8u);
  EXPECT_GT(untouched, report->tiles_rewritten) << "most tiles stay as they were";

  ASSERT_TRUE(BuildTilePyramid(*store_, info_, options_).ok());
  EXPECT_EQ(Differences(BytesOf(Stored()), BytesOf(after)), "")
      << "the update against a fresh build";
}

TEST_F(TileUpdateTest, EditsThatMoveTheHeightRangeRebuildEverything) {
  ASSERT_TRUE(BuildTilePyramid(*store_, info_, options_).ok());
  auto pyramid = TileStore(store_->db()).Pyramid(info_.id);
  ASSERT_TRUE(pyramid.ok() && pyramid->has_value());
  const double middle = ((*pyramid)->min_height + (*pyramid)->max_height) / 2;
  // The lowest vertex raised to the middle: the range shrinks.
  Edit([&](MeshTables& tables, LoadedSurface& s) {
    return MoveVertices(
        tables, s, [&](size_t v) { return s.vertex_ids[v] == (*pyramid)->min_vertex; }, middle);
  });
  auto report = UpdateTilePyramid(*store_, info_);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_TRUE(report->full_rebuild);
  const auto shrunk = BytesOf(Stored());
  ASSERT_TRUE(BuildTilePyramid(*store_, info_, options_).ok());
  EXPECT_EQ(Differences(BytesOf(Stored()), shrunk), "");

  // A vertex far from the extremes lowered below the range: it grows.
  Edit([&](MeshTables& tables, LoadedSurface& s) {
    return MoveVertices(
        tables, s, [&](size_t v) { return v == s.tin.vertices.size() / 2; },
        (*pyramid)->min_height - 50);
  });
  report = UpdateTilePyramid(*store_, info_);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_TRUE(report->full_rebuild);
  const auto grown = BytesOf(Stored());
  ASSERT_TRUE(BuildTilePyramid(*store_, info_, options_).ok());
  EXPECT_EQ(Differences(BytesOf(Stored()), grown), "");
}

}  // namespace
}  // namespace tinbase
