// SurfaceStore writes a Tin as topological rows and reads back exactly what it wrote.
#include "db/surface_store.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::ExpectStoreIntact;
using testing::TempDir;

class SurfaceStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = Store::Create(dir_.Path("s.tinbase"), "EPSG:32632");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
  }

  // Creates a surface in its own committed transaction.
  SurfaceInfo CreateSurface(const std::string& name, SurfaceKind kind, const Tin& tin) {
    auto tx = store_->BeginWrite();
    EXPECT_TRUE(tx.ok());
    SurfaceInfo spec;
    spec.name = name;
    spec.kind = kind;
    spec.method = "test";
    spec.tolerance = 0.5;
    auto info = SurfaceStore(*store_).Create(spec, tin);
    EXPECT_TRUE(info.ok()) << info.status().ToString();
    EXPECT_TRUE((*tx)->Commit().ok());
    return info.ok() ? *info : SurfaceInfo{};
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
};

// Tag value of a triangle, or "" without one.
std::string TagOf(const Tin& tin, const TinTriangle& t) {
  return t.tag == kNoTag ? "" : tin.tags[t.tag];
}

std::set<std::pair<uint32_t, uint32_t>> ConstraintSet(const Tin& tin) {
  std::set<std::pair<uint32_t, uint32_t>> out;
  for (auto [a, b] : tin.constraints) out.emplace(std::min(a, b), std::max(a, b));
  return out;
}

// Loaded rows are in id order and ids are handed out in Tin order, so positions match.
void ExpectSameTin(const Tin& expected, const Tin& actual) {
  ASSERT_EQ(expected.vertices.size(), actual.vertices.size());
  for (size_t i = 0; i < expected.vertices.size(); ++i) {
    EXPECT_EQ(expected.vertices[i].x, actual.vertices[i].x);
    EXPECT_EQ(expected.vertices[i].y, actual.vertices[i].y);
    EXPECT_EQ(expected.vertices[i].z, actual.vertices[i].z);
    EXPECT_EQ(expected.vertices[i].kind, actual.vertices[i].kind);
  }
  ASSERT_EQ(expected.triangles.size(), actual.triangles.size());
  for (size_t t = 0; t < expected.triangles.size(); ++t) {
    const TinTriangle& e = expected.triangles[t];
    const TinTriangle& a = actual.triangles[t];
    EXPECT_EQ(e.v, a.v) << "triangle " << t;
    EXPECT_EQ(e.n, a.n) << "triangle " << t;
    EXPECT_EQ(e.visible, a.visible);
    EXPECT_EQ(TagOf(expected, e), TagOf(actual, a));
  }
  EXPECT_EQ(ConstraintSet(expected), ConstraintSet(actual));
}

TEST_F(SurfaceStoreTest, CreateThenLoadRoundTrips) {
  const Tin tin = testing::RandomDelaunayTin({.points = 3000, .seed = 7, .ring = true});
  ASSERT_FALSE(tin.constraints.empty());
  const SurfaceInfo info = CreateSurface("bedrock", SurfaceKind::kDelaunay, tin);
  EXPECT_GT(info.id, 0);
  EXPECT_GT(info.blocks.size, 0);

  SurfaceStore surfaces(*store_);
  auto loaded = surfaces.Load(info);
  ASSERT_TRUE(loaded.ok()) << loaded.status().ToString();
  ExpectSameTin(tin, loaded->tin);
  ASSERT_EQ(loaded->vertex_ids.size(), tin.vertices.size());
  ASSERT_EQ(loaded->triangle_ids.size(), tin.triangles.size());

  auto found = surfaces.Find("bedrock");
  ASSERT_TRUE(found.ok());
  EXPECT_EQ(found->id, info.id);
  EXPECT_EQ(found->kind, SurfaceKind::kDelaunay);
  EXPECT_EQ(found->method, "test");
  EXPECT_EQ(found->tolerance, 0.5);
  EXPECT_FALSE(found->dem.has_value());
  EXPECT_EQ(found->blocks.origin_x, info.blocks.origin_x);
  EXPECT_EQ(found->blocks.size, info.blocks.size);

  auto counts = surfaces.Count(info);
  ASSERT_TRUE(counts.ok());
  EXPECT_EQ(counts->vertices, static_cast<int64_t>(tin.vertices.size()));
  EXPECT_EQ(counts->triangles, static_cast<int64_t>(tin.triangles.size()));
  EXPECT_EQ(counts->visible_triangles,
            std::count_if(tin.triangles.begin(), tin.triangles.end(),
                          [](const TinTriangle& t) { return t.visible; }));
  EXPECT_EQ(counts->constraints, static_cast<int64_t>(tin.constraints.size()));
  EXPECT_EQ(counts->features, 0);
  ExpectStoreIntact(*store_);
}

TEST_F(SurfaceStoreTest, RowAccessorsAgreeWithLoad) {
  const Tin tin = testing::RandomDelaunayTin({.points = 500, .seed = 3, .ring = true});
  const SurfaceInfo info = CreateSurface("terrain", SurfaceKind::kDelaunay, tin);
  const SurfaceInfo other =
      CreateSurface("other", SurfaceKind::kFree, testing::PerturbedGridTin(5, 5, 1));
  SurfaceStore surfaces(*store_);
  auto loaded = surfaces.Load(info);
  ASSERT_TRUE(loaded.ok());
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    auto row = surfaces.Triangle(info, loaded->triangle_ids[t]);
    ASSERT_TRUE(row.ok()) << row.status().ToString();
    const TinTriangle& tri = tin.triangles[t];
    std::array<TinVertex, 3> corner;
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(row->v[i], loaded->vertex_ids[tri.v[i]]);
      if (tri.n[i] == kNoNeighbour)
        EXPECT_FALSE(row->n[i].has_value());
      else
        EXPECT_EQ(row->n[i], loaded->triangle_ids[tri.n[i]]);
      corner[i] = tin.vertices[tri.v[i]];
    }
    EXPECT_EQ(row->visible, tri.visible);
    EXPECT_EQ(row->tag.value_or(""), TagOf(tin, tri));
    EXPECT_EQ(row->block, CentroidBlock(info.blocks, corner[0].x, corner[0].y, corner[1].x,
                                        corner[1].y, corner[2].x, corner[2].y));
    auto jump = surfaces.AnyTriangleInBlock(info, row->block);
    ASSERT_TRUE(jump.ok() && jump->has_value());
    EXPECT_EQ(surfaces.Triangle(info, **jump)->block, row->block);
  }
  for (size_t i = 0; i < tin.vertices.size(); ++i) {
    auto v = surfaces.Vertex(info, loaded->vertex_ids[i]);
    ASSERT_TRUE(v.ok());
    EXPECT_EQ(v->x, tin.vertices[i].x);
    EXPECT_EQ(v->z, tin.vertices[i].z);
    EXPECT_EQ(v->kind, tin.vertices[i].kind);
  }
  // Ids of one surface are not found through another.
  auto wrong = surfaces.Triangle(other, loaded->triangle_ids[0]);
  ASSERT_FALSE(wrong.ok());
  EXPECT_EQ(wrong.status().code(), StatusCode::kNotFound);
  EXPECT_NE(wrong.status().message().find("'other'"), std::string::npos);
  EXPECT_EQ(surfaces.Vertex(other, loaded->vertex_ids[0]).status().code(), StatusCode::kNotFound);
  auto empty_block = surfaces.AnyTriangleInBlock(
      info, BlockGrid::Pack(BlockGrid::kStride - 1, BlockGrid::kStride - 1));
  ASSERT_TRUE(empty_block.ok());
  EXPECT_FALSE(empty_block->has_value());
  auto any = surfaces.AnyTriangle(info);
  ASSERT_TRUE(any.ok());
  EXPECT_TRUE(std::binary_search(loaded->triangle_ids.begin(), loaded->triangle_ids.end(), *any));

  auto list = surfaces.List();
  ASSERT_TRUE(list.ok());
  ASSERT_EQ(list->size(), 2u);
  EXPECT_EQ((*list)[0].name, "other");  // by name
  EXPECT_EQ((*list)[1].name, "terrain");
  EXPECT_EQ((*list)[0].kind, SurfaceKind::kFree);
  ExpectStoreIntact(*store_);
}

TEST_F(SurfaceStoreTest, TakenNameIsAConflictAndMissingNameNotFound) {
  const Tin tin = testing::PerturbedGridTin(4, 4, 2);
  CreateSurface("terrain", SurfaceKind::kFree, tin);
  const auto before = testing::TableChecksums(store_->path());
  {
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    SurfaceInfo spec;
    spec.name = "terrain";
    spec.method = "test";
    auto again = SurfaceStore(*store_).Create(spec, tin);
    ASSERT_FALSE(again.ok());
    EXPECT_EQ(again.status().code(), StatusCode::kConflict);
    EXPECT_NE(again.status().message().find("'terrain'"), std::string::npos);
  }
  EXPECT_EQ(testing::TableChecksums(store_->path()), before);
  auto missing = SurfaceStore(*store_).Find("nowhere");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.status().code(), StatusCode::kNotFound);
  EXPECT_EQ(missing.status().message(), "no surface named 'nowhere'");
}

TEST_F(SurfaceStoreTest, BadIndicesAreRejectedBeforeAnythingIsWritten) {
  Tin tin = testing::PerturbedGridTin(3, 3, 4);
  tin.triangles[2].v[1] = 99;
  auto tx = store_->BeginWrite();
  ASSERT_TRUE(tx.ok());
  SurfaceInfo spec;
  spec.name = "broken";
  spec.method = "test";
  auto created = SurfaceStore(*store_).Create(spec, tin);
  ASSERT_FALSE(created.ok());
  EXPECT_EQ(created.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(created.status().message().find("triangle 2: vertex 99"), std::string::npos)
      << created.status().message();
  EXPECT_EQ(*store_->db().QueryInt("SELECT count(*) FROM surfaces"), 0);

  Tin nan = testing::PerturbedGridTin(3, 3, 4);
  nan.vertices[4].z = std::nan("");
  auto refused = SurfaceStore(*store_).Create(spec, nan);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().message(), "surface 'broken': vertex 4: coordinates not finite");
}

TEST_F(SurfaceStoreTest, TagsAreOneDictionaryAcrossSurfaces) {
  const Tin a = testing::RandomDelaunayTin({.points = 300, .seed = 1, .ring = true});
  const Tin b = testing::RandomDelaunayTin({.points = 300, .seed = 2, .ring = true});
  CreateSurface("a", SurfaceKind::kDelaunay, a);
  CreateSurface("b", SurfaceKind::kDelaunay, b);
  EXPECT_EQ(*store_->db().QueryInt("SELECT count(*) FROM tags"), 2);  // granite, schist
  ExpectStoreIntact(*store_);
}

TEST_F(SurfaceStoreTest, ReplaceSwapsTheRowsOfOneSurfaceOnly) {
  const SurfaceInfo keep =
      CreateSurface("keep", SurfaceKind::kFree, testing::PerturbedGridTin(6, 6, 5));
  const SurfaceInfo info =
      CreateSurface("terrain", SurfaceKind::kDelaunay,
                    testing::RandomDelaunayTin({.points = 400, .seed = 5, .ring = true}));
  SurfaceStore surfaces(*store_);
  const auto kept_before = surfaces.Load(keep);
  ASSERT_TRUE(kept_before.ok());

  const Tin replacement = testing::RandomDelaunayTin({.points = 250, .seed = 6});
  {
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    auto replaced = surfaces.Replace(info, replacement);
    ASSERT_TRUE(replaced.ok()) << replaced.status().ToString();
    EXPECT_EQ(replaced->triangle_ids.size(), replacement.triangles.size());
    ASSERT_TRUE((*tx)->Commit().ok());
  }
  auto loaded = surfaces.Load(info);
  ASSERT_TRUE(loaded.ok());
  ExpectSameTin(replacement, loaded->tin);
  auto counts = surfaces.Count(info);
  EXPECT_EQ(counts->vertices, static_cast<int64_t>(replacement.vertices.size()));
  EXPECT_EQ(counts->constraints, 0);
  auto kept_after = surfaces.Load(keep);
  ASSERT_TRUE(kept_after.ok());
  ExpectSameTin(kept_before->tin, kept_after->tin);
  EXPECT_EQ(kept_before->triangle_ids, kept_after->triangle_ids);
  ExpectStoreIntact(*store_);
}

TEST_F(SurfaceStoreTest, AMillionTrianglesWriteInSeconds) {
  const Tin tin = testing::PerturbedGridTin(708, 708, 9, 10.0);  // 2 * 707^2 = 999698 triangles
  const auto start = std::chrono::steady_clock::now();
  const SurfaceInfo info = CreateSurface("big", SurfaceKind::kFree, tin);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("wrote %zu triangles, %zu vertices in %.2f s\n", tin.triangles.size(),
              tin.vertices.size(), seconds);
  EXPECT_LT(seconds, 15.0);  // a few seconds alone; slack for a shared machine
  auto counts = SurfaceStore(*store_).Count(info);
  ASSERT_TRUE(counts.ok());
  EXPECT_EQ(counts->triangles, static_cast<int64_t>(tin.triangles.size()));
  // Reading back and checking are O(n log n) too.
  const auto read = std::chrono::steady_clock::now();
  auto loaded = SurfaceStore(*store_).Load(info);
  ASSERT_TRUE(loaded.ok());
  EXPECT_EQ(loaded->tin.triangles.size(), tin.triangles.size());
  EXPECT_EQ(loaded->tin.triangles[123456].n, tin.triangles[123456].n);
  const auto check = std::chrono::steady_clock::now();
  ExpectStoreIntact(*store_);
  const auto done = std::chrono::steady_clock::now();
  std::printf("load %.2f s, check %.2f s\n", std::chrono::duration<double>(check - read).count(),
              std::chrono::duration<double>(done - check).count());
}

}  // namespace
}  // namespace tinbase
