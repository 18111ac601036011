// MeshCache's bulk reads on the Hamersley DEM with two filled polygons: ReadBlocks holds what the
// store holds, the owners it reads with the vertices answer every edge as a lookup per edge
// does, and the cache's writes keep those answers current.
#include "db/mesh_cache.h"

#include <gtest/gtest.h>

#include <set>

#include "db/dem_store.h"
#include "db/edit/mesh_delta.h"
#include "db/feature_store.h"
#include "db/polygon_editor.h"
#include "db/surface_builder.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::Ngon;
using testing::StoreTarget;
using testing::TempDir;
using testing::WritePolygons;

constexpr double kCx = 539300, kCy = 7497340, kCell = 344.404386931320971;  // Hamersley

class MeshCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = Store::Create(StoreTarget(dir_, "s.tinbase"), "");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    ASSERT_TRUE(DemStore(*store_).Import({DataPath("geology/hamersley/dtm_rp.tif")}, {}).ok());
    SurfaceBuildOptions build;
    build.surface = "terrain";
    build.greedy.tolerance = 5;
    ASSERT_TRUE(BuildSurfaceFromDem(*store_, build).ok());
    PolygonAddOptions add;
    add.surface = "terrain";
    add.file = WritePolygons(
        dir_, "p.geojson",
        {{Ngon(kCx, kCy, 20 * kCell, 60)}, {Ngon(kCx + 15 * kCell, kCy, 12 * kCell, 40, 0.4)}});
    add.mode = FeatureMode::kFill;
    add.tag_field = "unit";
    auto added = AddPolygons(*store_, add);
    ASSERT_TRUE(added.ok()) << added.status().ToString();
    auto surface = SurfaceStore(*store_).Find("terrain");
    ASSERT_TRUE(surface.ok());
    surface_ = *surface;
    auto features = LoadFeatures(*store_, surface_);
    ASSERT_TRUE(features.ok());
    ASSERT_EQ(features->size(), 2u);
    std::set<int64_t> blocks;
    for (const EditorFeature& f : *features)
      for (int64_t b : RingBlocksOf(f, surface_.blocks)) blocks.insert(b);
    ring_blocks_.assign(blocks.begin(), blocks.end());
  }

  // The triangles of ring_blocks_, read through `cache`.
  std::vector<int64_t> RingTriangles(MeshCache& cache) {
    std::vector<int64_t> ids;
    for (int64_t b : ring_blocks_) {
      const int64_t by = BlockGrid::RowOfPacked(b), bx = BlockGrid::ColumnOfPacked(b);
      EXPECT_TRUE(cache.TrianglesInBlocks(by, bx, bx, &ids).ok());
    }
    return ids;
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
  SurfaceInfo surface_;
  std::vector<int64_t> ring_blocks_;  // the blocks the polygons' rings pass, sorted
};

TEST_F(MeshCacheTest, ReadBlocksHoldsTheRowsAsStored) {
  MeshCache cache(*store_, surface_);
  ASSERT_TRUE(cache.ReadBlocks(ring_blocks_).ok());
  EXPECT_TRUE(cache.VerifyAgainstStore().ok()) << cache.VerifyAgainstStore().ToString();
  MeshCache fresh(*store_, surface_);
  EXPECT_EQ(RingTriangles(cache), RingTriangles(fresh));
}

TEST_F(MeshCacheTest, OwnersReadWithTheVerticesAnswerAsLookupsDo) {
  MeshCache cache(*store_, surface_);
  ASSERT_TRUE(cache.ReadBlocks(ring_blocks_).ok());
  MeshCache fresh(*store_, surface_);
  size_t constrained = 0, edges = 0;
  for (int64_t t : RingTriangles(cache)) {
    auto tri = cache.Triangle(t);
    ASSERT_TRUE(tri.ok());
    const std::array<int64_t, 3> v = (*tri)->v;
    for (int i = 0; i < 3; ++i) {
      auto held = cache.Owners(v[i], v[(i + 1) % 3]);
      auto looked_up = fresh.Owners(v[i], v[(i + 1) % 3]);
      ASSERT_TRUE(held.ok() && looked_up.ok());
      std::vector<int64_t> a = **held, b = **looked_up;
      std::sort(a.begin(), a.end());
      std::sort(b.begin(), b.end());
      EXPECT_EQ(a, b) << "edge " << v[i] << " - " << v[(i + 1) % 3];
      constrained += !b.empty();
      ++edges;
    }
  }
  EXPECT_GT(constrained, 100u) << "the rings' edges are constrained";
  EXPECT_GT(edges, 3 * constrained);
}

// An edge from a vertex whose constraint rows were read is unconstrained when the cache does not
// hold it: a delta adding a constraint row must therefore record a new owner of such an edge, and
// one splitting the constraint drop it.
TEST_F(MeshCacheTest, OwnersReadWithTheVerticesFollowTheCacheWrites) {
  MeshCache cache(*store_, surface_);
  ASSERT_TRUE(cache.ReadBlocks(ring_blocks_).ok());
  std::optional<std::pair<int64_t, int64_t>> free_edge;
  for (int64_t t : RingTriangles(cache)) {
    const std::array<int64_t, 3> v = (*cache.Triangle(t))->v;
    for (int i = 0; i < 3 && !free_edge; ++i)
      if ((*cache.Owners(v[i], v[(i + 1) % 3]))->empty()) free_edge = {{v[i], v[(i + 1) % 3]}};
    if (free_edge) break;
  }
  ASSERT_TRUE(free_edge.has_value());
  const auto [a, b] = *free_edge;
  MeshDelta added;
  added.surface = surface_.id;
  added.added_constraints = {{EdgeKey(a, b), 42}};
  cache.Apply(added);
  EXPECT_EQ(**cache.Owners(b, a), std::vector<int64_t>{42});
  MeshDelta split;
  split.surface = surface_.id;
  split.split_constraints = {EdgeKey(a, b)};
  cache.Apply(split);
  EXPECT_TRUE((*cache.Owners(a, b))->empty());
}

}  // namespace
}  // namespace tinbase
