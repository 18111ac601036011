// SurfaceStore writes a Tin as topological rows and reads back exactly what it wrote.
#include "db/surface_store.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <compare>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::ExpectStoreIntact;
using testing::StoreTarget;
using testing::TempDir;

class SurfaceStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = Store::Create(StoreTarget(dir_, "s.tinbase"), "EPSG:32632");
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

// The store may give rows any ids (it writes them in index order), so the two TINs are compared
// by what the rows say: every vertex by its coordinates, every triangle by its corners' and its
// neighbours' corners' coordinates, with its visibility and tag.
using Xyz = std::tuple<double, double, double, VertexKind>;
using TriangleKey = std::array<Xyz, 3>;
struct TriangleRecord {
  TriangleKey corners;
  std::array<std::optional<TriangleKey>, 3> neighbours;
  bool visible;
  std::string tag;
  // NOLINTNEXTLINE(modernize-use-nullptr): clang-tidy 14 misreads the synthesized comparison.
  auto operator<=>(const TriangleRecord&) const = default;
};

std::vector<TriangleRecord> Records(const Tin& tin) {
  const auto corners = [&](const TinTriangle& t) {
    TriangleKey key;
    for (int i = 0; i < 3; ++i) {
      const TinVertex& v = tin.vertices[t.v[i]];
      key[i] = Xyz{v.x, v.y, v.z, v.kind};
    }
    return key;
  };
  std::vector<TriangleRecord> out;
  for (const TinTriangle& t : tin.triangles) {
    TriangleRecord r{corners(t), {}, t.visible, TagOf(tin, t)};
    for (int i = 0; i < 3; ++i)
      if (t.n[i] != kNoNeighbour) r.neighbours[i] = corners(tin.triangles[t.n[i]]);
    out.push_back(std::move(r));
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<Xyz> VertexRecords(const Tin& tin) {
  std::vector<Xyz> out;
  for (const TinVertex& v : tin.vertices) out.emplace_back(v.x, v.y, v.z, v.kind);
  std::sort(out.begin(), out.end());
  return out;
}

std::set<std::pair<Xyz, Xyz>> ConstraintRecords(const Tin& tin) {
  std::set<std::pair<Xyz, Xyz>> out;
  for (auto [a, b] : tin.constraints) {
    const TinVertex &p = tin.vertices[a], &q = tin.vertices[b];
    out.emplace(std::minmax(Xyz{p.x, p.y, p.z, p.kind}, Xyz{q.x, q.y, q.z, q.kind}));
  }
  return out;
}

void ExpectSameTin(const Tin& expected, const Tin& actual) {
  EXPECT_EQ(VertexRecords(expected), VertexRecords(actual));
  EXPECT_EQ(ConstraintRecords(expected), ConstraintRecords(actual));
  ASSERT_EQ(expected.triangles.size(), actual.triangles.size());
  EXPECT_TRUE(Records(expected) == Records(actual));
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
  for (size_t t = 0; t < loaded->tin.triangles.size(); ++t) {
    auto row = surfaces.Triangle(info, loaded->triangle_ids[t]);
    ASSERT_TRUE(row.ok()) << row.status().ToString();
    const TinTriangle& tri = loaded->tin.triangles[t];
    std::array<TinVertex, 3> corner;
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(row->v[i], loaded->vertex_ids[tri.v[i]]);
      if (tri.n[i] == kNoNeighbour)
        EXPECT_FALSE(row->n[i].has_value());
      else
        EXPECT_EQ(row->n[i], loaded->triangle_ids[tri.n[i]]);
      corner[i] = loaded->tin.vertices[tri.v[i]];
    }
    EXPECT_EQ(row->visible, tri.visible);
    std::string tag;
    if (row->tag) {
      auto value = surfaces.TagValue(info, *row->tag);
      ASSERT_TRUE(value.ok()) << value.status().ToString();
      tag = *value;
    }
    EXPECT_EQ(tag, TagOf(loaded->tin, tri));
    EXPECT_EQ(row->block, CentroidBlock(info.blocks, corner[0].x, corner[0].y, corner[1].x,
                                        corner[1].y, corner[2].x, corner[2].y));
    auto jump = surfaces.AnyTriangleInBlock(info, row->block);
    ASSERT_TRUE(jump.ok() && jump->has_value());
    EXPECT_EQ(surfaces.Triangle(info, **jump)->block, row->block);
  }
  for (size_t i = 0; i < loaded->tin.vertices.size(); ++i) {
    auto v = surfaces.Vertex(info, loaded->vertex_ids[i]);
    ASSERT_TRUE(v.ok());
    EXPECT_EQ(v->x, loaded->tin.vertices[i].x);
    EXPECT_EQ(v->z, loaded->tin.vertices[i].z);
    EXPECT_EQ(v->kind, loaded->tin.vertices[i].kind);
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

// Load names the row and the id a broken reference points to; a tag id the tags table lacks
// loads as no tag (check reports it), and ids SQLite allows but tinbase never writes (negative)
// load like any other. Each change is made in a transaction that is rolled back.
TEST_F(SurfaceStoreTest, LoadNamesBrokenReferencesAndTakesAnyRowId) {
  const Tin tin = testing::RandomDelaunayTin({.points = 300, .seed = 3, .ring = true});
  ASSERT_FALSE(tin.tags.empty());
  ASSERT_FALSE(tin.constraints.empty());
  const SurfaceInfo info = CreateSurface("bedrock", SurfaceKind::kDelaunay, tin);
  Connection& db = store_->db();
  const int64_t first = *db.QueryInt("SELECT min(id) FROM triangles");
  const int64_t with_neighbour = *db.QueryInt("SELECT min(id) FROM triangles WHERE n1 IS NOT NULL");
  const int64_t tagged = *db.QueryInt("SELECT min(id) FROM triangles WHERE tag IS NOT NULL");
  const auto load_after = [&](const std::vector<std::string>& statements) {
    auto tx = store_->BeginWrite();
    EXPECT_TRUE(tx.ok());
    for (const std::string& sql : statements) EXPECT_TRUE(db.Exec(sql).ok()) << sql;
    return SurfaceStore(*store_).Load(info);  // the transaction rolls back when it goes
  };
  const auto expect_corrupt = [&](const std::vector<std::string>& statements,
                                  const std::string& message) {
    auto loaded = load_after(statements);
    ASSERT_FALSE(loaded.ok()) << message;
    EXPECT_EQ(loaded.status().code(), StatusCode::kCorruption);
    EXPECT_NE(loaded.status().message().find(message), std::string::npos)
        << loaded.status().message();
  };
  const std::string id = std::to_string(first);
  expect_corrupt({"UPDATE triangles SET v1 = 999999 WHERE id = " + id},
                 "surface 'bedrock', triangle " + id + ": vertex 999999 is missing");
  expect_corrupt({"UPDATE triangles SET n1 = 888888 WHERE id = " + std::to_string(with_neighbour)},
                 "triangle " + std::to_string(with_neighbour) + ": neighbour 888888 is missing");
  expect_corrupt({"INSERT INTO constraints(surface, va, vb) VALUES (" + std::to_string(info.id) +
                  ", 1, 777777)"},
                 "constraint (1, 777777) names a missing vertex");

  auto unknown_tag =
      load_after({"UPDATE triangles SET tag = 424242 WHERE id = " + std::to_string(tagged)});
  ASSERT_TRUE(unknown_tag.ok()) << unknown_tag.status().ToString();
  const auto at =
      std::find(unknown_tag->triangle_ids.begin(), unknown_tag->triangle_ids.end(), tagged) -
      unknown_tag->triangle_ids.begin();
  EXPECT_EQ(unknown_tag->tin.triangles[static_cast<size_t>(at)].tag, kNoTag);

  // Every vertex and triangle moved to a negative id, references following: the same TIN.
  const std::string shift = "-1000000 - id";
  const std::string flip_ref = [] {
    std::string sql = "UPDATE triangles SET ";
    for (const char* v : {"v0", "v1", "v2"}) sql += std::string(v) + " = -1000000 - " + v + ", ";
    for (const char* n : {"n0", "n1", "n2"}) sql += std::string(n) + " = -1000000 - " + n + ", ";
    return sql + "id = -1000000 - id";
  }();
  auto negative =
      load_after({"PRAGMA defer_foreign_keys = ON", "UPDATE vertices SET id = " + shift, flip_ref,
                  "UPDATE constraints SET va = -1000000 - vb, vb = -1000000 - va"});
  ASSERT_TRUE(negative.ok()) << negative.status().ToString();
  EXPECT_LT(negative->vertex_ids.front(), 0);
  ExpectSameTin(tin, negative->tin);
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

// `tin` handed over as a streamed triangulation would: triangles sorted by `order` (stable), in
// `count` batches, a neighbour in a later batch left open and linked by the batch that holds it.
// `sorted` receives the Tin in that order, as the store should hold it.
std::vector<TriangleBatch> InBatches(const Tin& tin, const TriangleOrder& order, size_t count,
                                     Tin* sorted) {
  std::vector<uint32_t> by_key(tin.triangles.size());
  for (uint32_t t = 0; t < by_key.size(); ++t) by_key[t] = t;
  std::stable_sort(by_key.begin(), by_key.end(), [&](uint32_t a, uint32_t b) {
    return order(tin.triangles[a]) < order(tin.triangles[b]);
  });
  std::vector<int32_t> rank(by_key.size());
  for (size_t r = 0; r < by_key.size(); ++r) rank[by_key[r]] = static_cast<int32_t>(r);
  *sorted = tin;
  for (size_t r = 0; r < by_key.size(); ++r) {
    sorted->triangles[r] = tin.triangles[by_key[r]];
    for (int32_t& n : sorted->triangles[r].n)
      if (n != kNoNeighbour) n = rank[static_cast<size_t>(n)];
  }
  const size_t size = (by_key.size() + count - 1) / count;
  std::vector<TriangleBatch> batches(count);
  for (size_t b = 0; b < count; ++b) {
    TriangleBatch& batch = batches[b];
    batch.first = std::min(b * size, by_key.size());
    const size_t end = std::min(batch.first + size, by_key.size());
    for (size_t t = batch.first; t < end; ++t) {
      TinTriangle tri = sorted->triangles[t];
      for (int i = 0; i < 3; ++i) {
        const int32_t n = tri.n[i];
        if (n == kNoNeighbour || static_cast<size_t>(n) < end) continue;
        tri.n[i] = kNoNeighbour;
        batches[static_cast<size_t>(n) / size].links.push_back({static_cast<uint32_t>(t), i, n});
      }
      batch.triangles.push_back(tri);
      batch.keys.push_back(order(tri));
    }
  }
  return batches;
}

// The bulk path (triangles handed over in batches from a second thread while the vertices are
// written) stores the triangulation, its neighbours linked late included, as its rows in batch
// order.
TEST_F(SurfaceStoreTest, CreateWhileTriangulatingStoresTheBatchesAndTheirLateLinks) {
  const Tin tin = testing::RandomDelaunayTin({.points = 5000, .seed = 11});
  auto tx = store_->BeginWrite();
  ASSERT_TRUE(tx.ok());
  SurfaceInfo spec;
  spec.name = "bulk";
  spec.kind = SurfaceKind::kDelaunay;
  spec.method = "test";
  Tin sorted;
  size_t links = 0;
  auto info = SurfaceStore(*store_).CreateWhileTriangulating(
      spec, tin.vertices, [&](const TriangleOrder& order, const TriangleSink& finished) {
        for (TriangleBatch& batch : InBatches(tin, order, 4, &sorted)) {
          links += batch.links.size();
          finished(std::move(batch));
        }
        return Status::Ok();
      });
  ASSERT_TRUE(info.ok()) << info.status().ToString();
  ASSERT_TRUE((*tx)->Commit().ok());
  EXPECT_GT(links, 0u);
  auto found = SurfaceStore(*store_).Find("bulk");
  ASSERT_TRUE(found.ok());
  auto loaded = SurfaceStore(*store_).Load(*found);
  ASSERT_TRUE(loaded.ok()) << loaded.status().ToString();
  ExpectSameTin(sorted, loaded->tin);
  ExpectStoreIntact(*store_);
}

// A triangulation that fails, or hands over a batch whose indices do not fit, leaves nothing
// once the transaction rolls back.
TEST_F(SurfaceStoreTest, CreateWhileTriangulatingPassesErrorsOnAndChecksBatches) {
  const Tin tin = testing::RandomDelaunayTin({.points = 500, .seed = 3});
  SurfaceInfo spec;
  spec.name = "bulk";
  spec.kind = SurfaceKind::kDelaunay;
  spec.method = "test";
  {
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    auto failed = SurfaceStore(*store_).CreateWhileTriangulating(
        spec, tin.vertices, [](const TriangleOrder&, const TriangleSink&) {
          return Status::InvalidArgument("no triangle");
        });
    EXPECT_EQ(failed.status().message(), "no triangle");
  }
  const auto bad_batch = [&](const std::function<void(std::vector<TriangleBatch>&)>& spoil) {
    auto tx = store_->BeginWrite();
    EXPECT_TRUE(tx.ok());
    return SurfaceStore(*store_)
        .CreateWhileTriangulating(spec, tin.vertices,
                                  [&](const TriangleOrder& order, const TriangleSink& finished) {
                                    Tin sorted;
                                    auto batches = InBatches(tin, order, 2, &sorted);
                                    spoil(batches);
                                    for (TriangleBatch& batch : batches) finished(std::move(batch));
                                    return Status::Ok();
                                  })
        .status();
  };
  const Status vertex = bad_batch([&](auto& b) { b[1].triangles[3].v[1] = 500; });
  EXPECT_EQ(vertex.code(), StatusCode::kInvalidArgument);
  const Status gap = bad_batch([&](auto& b) { b[1].first += 1; });
  EXPECT_EQ(gap.code(), StatusCode::kInvalidArgument);
  const Status link = bad_batch([&](auto& b) {
    ASSERT_FALSE(b[1].links.empty());
    b[1].links[0].triangle = static_cast<uint32_t>(b[1].first);  // not written yet
  });
  EXPECT_EQ(link.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(SurfaceStore(*store_).Find("bulk").status().code(), StatusCode::kNotFound);
  EXPECT_EQ(*store_->db().QueryInt("SELECT count(*) FROM vertices"), 0);
  ExpectStoreIntact(*store_);
}

// A million triangles write, load back whole and check clean (speed is bench/'s business).
TEST_F(SurfaceStoreTest, AMillionTrianglesRoundTrip) {
  const Tin tin = testing::PerturbedGridTin(708, 708, 9, 10.0);  // 2 * 707^2 = 999698 triangles
  const SurfaceInfo info = CreateSurface("big", SurfaceKind::kFree, tin);
  auto counts = SurfaceStore(*store_).Count(info);
  ASSERT_TRUE(counts.ok());
  EXPECT_EQ(counts->triangles, static_cast<int64_t>(tin.triangles.size()));
  auto loaded = SurfaceStore(*store_).Load(info);
  ASSERT_TRUE(loaded.ok());
  ExpectSameTin(tin, loaded->tin);
  ExpectStoreIntact(*store_);
}

}  // namespace
}  // namespace tinbase
