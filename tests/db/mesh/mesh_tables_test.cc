// MeshTables reads back, by id, block, id range and whole surface, exactly the rows its bulk
// writes stored, keeps each surface's rows to itself, and reports a missing row as NotFound.
#include "db/mesh/mesh_tables.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "db/mesh_cache.h"
#include "db/surface_store.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::ExpectStoreIntact;
using testing::TempDir;

using Corners = std::array<std::pair<double, double>, 3>;  // sorted (x, y) of a triangle

Corners CornersOf(const std::array<TinVertex, 3>& v) {
  Corners c;
  for (int i = 0; i < 3; ++i) c[i] = {v[i].x, v[i].y};
  std::sort(c.begin(), c.end());
  return c;
}

// Every row of a cursor, with its id.
template <typename Cursor, typename Row>
std::vector<std::pair<int64_t, Row>> ReadAll(Result<Cursor> cursor) {
  std::vector<std::pair<int64_t, Row>> rows;
  EXPECT_TRUE(cursor.ok()) << cursor.status().ToString();
  if (!cursor.ok()) return rows;
  int64_t id = 0;
  for (Row row;;) {
    auto more = cursor->Next(&id, &row);
    EXPECT_TRUE(more.ok()) << more.status().ToString();
    if (!more.ok() || !*more) break;
    rows.emplace_back(id, row);
  }
  return rows;
}

std::vector<ConstraintRow> ReadAll(Result<ConstraintCursor> cursor) {
  std::vector<ConstraintRow> rows;
  EXPECT_TRUE(cursor.ok()) << cursor.status().ToString();
  if (!cursor.ok()) return rows;
  for (ConstraintRow row;;) {
    auto more = cursor->Next(&row);
    EXPECT_TRUE(more.ok()) << more.status().ToString();
    if (!more.ok() || !*more) break;
    rows.push_back(row);
  }
  return rows;
}

class MeshTablesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = Store::Create(testing::StoreTarget(dir_, "s.tinbase"), "EPSG:32632");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    // A surface with paint, tags and constraints (the ring), and a second one written after it.
    tin_ = testing::RandomDelaunayTin({.points = 400, .seed = 11, .ring = true});
    tin_.tags.push_back("basalt");
    for (size_t t = 0; t < tin_.triangles.size(); ++t) {
      if (t % 7 == 0) tin_.triangles[t].visible = false;
      if (t % 5 == 0) tin_.triangles[t].tag = static_cast<int32_t>(tin_.tags.size() - 1);
    }
    terrain_ = Create("terrain", tin_, SurfaceKind::kDelaunay);
    other_ = Create("other", testing::PerturbedGridTin(6, 6, 2), SurfaceKind::kFree);
  }

  SurfaceInfo Create(const std::string& name, const Tin& tin, SurfaceKind kind) {
    auto tx = store_->BeginWrite();
    EXPECT_TRUE(tx.ok());
    SurfaceInfo spec;
    spec.name = name;
    spec.kind = kind;
    spec.method = "test";
    auto info = SurfaceStore(*store_).Create(spec, tin);
    EXPECT_TRUE(info.ok()) << info.status().ToString();
    EXPECT_TRUE((*tx)->Commit().ok());
    return info.ok() ? *info : SurfaceInfo{};
  }

  std::vector<std::pair<int64_t, TriangleRow>> Triangles(MeshTables& tables) {
    return ReadAll<TriangleCursor, TriangleRow>(tables.Triangles());
  }
  std::vector<std::pair<int64_t, VertexRow>> Vertices(MeshTables& tables) {
    return ReadAll<VertexCursor, VertexRow>(tables.Vertices());
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
  Tin tin_;
  SurfaceInfo terrain_, other_;
};

TEST_F(MeshTablesTest, RowsRoundTrip) {
  MeshTables tables(store_->db(), terrain_);
  const auto vertices = Vertices(tables);
  ASSERT_EQ(vertices.size(), tin_.vertices.size());
  std::map<int64_t, VertexRow> vertex_by_id(vertices.begin(), vertices.end());
  EXPECT_EQ(vertex_by_id.size(), vertices.size());  // ids distinct
  std::multiset<std::tuple<double, double, double, VertexKind>> written, read;
  for (const TinVertex& v : tin_.vertices) written.insert({v.x, v.y, v.z, v.kind});
  for (size_t i = 0; i < vertices.size(); ++i) {
    const VertexRow& v = vertices[i].second;
    read.insert({v.x, v.y, v.z, v.kind});
    if (i > 0) {
      EXPECT_LT(vertices[i - 1].first, vertices[i].first);  // id order
    }
  }
  EXPECT_EQ(read, written);

  // Every triangle of the Tin comes back once, found by its corners, with its paint.
  std::map<Corners, const TinTriangle*> by_corners;
  for (const TinTriangle& t : tin_.triangles)
    by_corners[CornersOf({tin_.vertices[t.v[0]], tin_.vertices[t.v[1]], tin_.vertices[t.v[2]]})] =
        &t;
  const auto triangles = Triangles(tables);
  ASSERT_EQ(triangles.size(), tin_.triangles.size());
  std::set<int64_t> ids;
  for (const auto& [id, row] : triangles) ids.insert(id);
  for (size_t k = 0; k < triangles.size(); ++k) {
    const auto& [id, row] = triangles[k];
    if (k > 0) {
      EXPECT_LT(triangles[k - 1].first, id);
    }
    std::array<TinVertex, 3> corner;
    for (int i = 0; i < 3; ++i) {
      ASSERT_TRUE(vertex_by_id.count(row.v[i])) << "triangle " << id;
      corner[i] = vertex_by_id[row.v[i]];
      if (row.n[i]) {
        EXPECT_TRUE(ids.count(*row.n[i])) << "triangle " << id;
      }
    }
    auto found = by_corners.find(CornersOf(corner));
    ASSERT_NE(found, by_corners.end()) << "triangle " << id;
    const TinTriangle& t = *found->second;
    EXPECT_EQ(row.visible, t.visible) << "triangle " << id;
    ASSERT_EQ(row.tag.has_value(), t.tag != kNoTag) << "triangle " << id;
    if (row.tag) {
      auto value = tables.TagValue(*row.tag);
      ASSERT_TRUE(value.ok()) << value.status().ToString();
      EXPECT_EQ(*value, tin_.tags[t.tag]);
    }
    EXPECT_EQ(row.block, CentroidBlock(terrain_.blocks, corner[0].x, corner[0].y, corner[1].x,
                                       corner[1].y, corner[2].x, corner[2].y));
    // By id: the same row.
    auto by_id = tables.Triangle(id);
    ASSERT_TRUE(by_id.ok()) << by_id.status().ToString();
    EXPECT_EQ(*by_id, row);
    auto has = tables.HasTriangle(id);
    ASSERT_TRUE(has.ok());
    EXPECT_TRUE(*has);
  }
  for (const auto& [id, v] : vertices) {
    auto by_id = tables.Vertex(id);
    ASSERT_TRUE(by_id.ok()) << by_id.status().ToString();
    EXPECT_EQ(by_id->x, v.x);
    EXPECT_EQ(by_id->y, v.y);
    EXPECT_EQ(by_id->z, v.z);
    EXPECT_EQ(by_id->kind, v.kind);
  }

  // Constraints: the ring's edges, smaller vertex first, without feature, in (va, vb) order.
  const auto constraints = ReadAll(tables.Constraints());
  ASSERT_FALSE(tin_.constraints.empty());
  ASSERT_EQ(constraints.size(), tin_.constraints.size());
  for (size_t k = 0; k < constraints.size(); ++k) {
    const ConstraintRow& c = constraints[k];
    EXPECT_LT(c.va, c.vb);
    EXPECT_FALSE(c.feature.has_value());
    if (k > 0) {
      EXPECT_LT(std::make_pair(constraints[k - 1].va, constraints[k - 1].vb),
                std::make_pair(c.va, c.vb));
    }
    auto owners = tables.Owners(c.va, c.vb);
    ASSERT_TRUE(owners.ok());
    EXPECT_EQ(*owners, std::vector<int64_t>{0});
  }
  auto unconstrained = tables.Owners(triangles[0].second.v[0], triangles[0].second.v[0] + 1000000);
  ASSERT_TRUE(unconstrained.ok());
  EXPECT_TRUE(unconstrained->empty());

  auto counts = tables.Count();
  ASSERT_TRUE(counts.ok());
  EXPECT_EQ(counts->vertices, static_cast<int64_t>(tin_.vertices.size()));
  EXPECT_EQ(counts->triangles, static_cast<int64_t>(tin_.triangles.size()));
  EXPECT_EQ(counts->visible_triangles,
            std::count_if(tin_.triangles.begin(), tin_.triangles.end(),
                          [](const TinTriangle& t) { return t.visible; }));
  EXPECT_EQ(counts->constraints, static_cast<int64_t>(tin_.constraints.size()));
  auto constraint_count = tables.CountConstraints();
  ASSERT_TRUE(constraint_count.ok());
  EXPECT_EQ(*constraint_count, counts->constraints);
  ExpectStoreIntact(*store_);
}

TEST_F(MeshTablesTest, ReadsByBlock) {
  MeshTables tables(store_->db(), terrain_);
  const auto triangles = Triangles(tables);
  std::map<int64_t, std::vector<int64_t>> members;  // block -> ids ascending
  for (const auto& [id, row] : triangles) members[row.block].push_back(id);
  ASSERT_GT(members.size(), 4u);
  for (const auto& [block, ids] : members) {
    auto in_block = tables.TriangleIdsInBlock(block);
    ASSERT_TRUE(in_block.ok());
    EXPECT_EQ(*in_block, ids) << "block " << block;
    auto any = tables.AnyTriangleInBlock(block);
    ASSERT_TRUE(any.ok() && any->has_value());
    EXPECT_TRUE(std::binary_search(ids.begin(), ids.end(), **any));
  }
  // A run of blocks of one grid row: exactly the members of those blocks, by block then id, each
  // row as read by id.
  const int64_t row_of_first = BlockGrid::RowOfPacked(members.begin()->first);
  const int64_t first = BlockGrid::Pack(0, row_of_first);
  const int64_t last = BlockGrid::Pack(BlockGrid::kStride - 1, row_of_first);
  std::vector<int64_t> expected;
  for (const auto& [block, ids] : members)
    if (block >= first && block <= last) expected.insert(expected.end(), ids.begin(), ids.end());
  ASSERT_FALSE(expected.empty());
  const auto run = ReadAll<TriangleCursor, TriangleRow>(tables.TrianglesInBlocks(first, last));
  std::vector<int64_t> got;
  for (const auto& [id, row] : run) {
    got.push_back(id);
    EXPECT_EQ(row, *tables.Triangle(id));
  }
  EXPECT_EQ(got, expected);

  const int64_t empty = BlockGrid::Pack(BlockGrid::kStride - 1, BlockGrid::kStride - 1);
  auto none = tables.AnyTriangleInBlock(empty);
  ASSERT_TRUE(none.ok());
  EXPECT_FALSE(none->has_value());
  auto no_ids = tables.TriangleIdsInBlock(empty);
  ASSERT_TRUE(no_ids.ok());
  EXPECT_TRUE(no_ids->empty());
  auto any = tables.AnyTriangle();
  ASSERT_TRUE(any.ok() && any->has_value());
  EXPECT_TRUE(*tables.HasTriangle(**any));
}

TEST_F(MeshTablesTest, ReadsByIdRangeKeepToTheSurface) {
  MeshTables terrain(store_->db(), terrain_), other(store_->db(), other_);
  const auto mine = Vertices(terrain);
  const auto theirs = Vertices(other);
  ASSERT_FALSE(mine.empty());
  ASSERT_FALSE(theirs.empty());
  // A range over the end of one surface's ids and the start of the other's.
  const int64_t first = mine[mine.size() - 5].first, last = theirs[4].first;
  ASSERT_LT(first, last);
  const auto range = ReadAll<VertexCursor, VertexRow>(terrain.VerticesInIdRange(first, last));
  ASSERT_EQ(range.size(), 5u);
  for (size_t k = 0; k < range.size(); ++k) {
    EXPECT_EQ(range[k].first, mine[mine.size() - 5 + k].first);
    EXPECT_EQ(range[k].second.x, mine[mine.size() - 5 + k].second.x);
  }
  const auto from_other = ReadAll<VertexCursor, VertexRow>(other.VerticesInIdRange(first, last));
  ASSERT_EQ(from_other.size(), 5u);
  EXPECT_EQ(from_other.front().first, theirs[0].first);

  // Constraints by their smaller vertex.
  const auto constraints = ReadAll(terrain.Constraints());
  ASSERT_GE(constraints.size(), 4u);
  const int64_t lo = constraints[1].va, hi = constraints[constraints.size() - 2].va;
  size_t expected = 0;
  for (const ConstraintRow& c : constraints) expected += c.va >= lo && c.va <= hi;
  const auto from = ReadAll(terrain.ConstraintsFrom(lo, hi));
  EXPECT_EQ(from.size(), expected);
  for (const ConstraintRow& c : from) {
    EXPECT_GE(c.va, lo);
    EXPECT_LE(c.va, hi);
  }
  auto count = terrain.CountConstraintsFrom(lo, hi);
  ASSERT_TRUE(count.ok());
  EXPECT_EQ(*count, static_cast<int64_t>(expected));
  EXPECT_TRUE(ReadAll(other.ConstraintsFrom(lo, hi)).empty());
}

// Regression: on PostgreSQL an updated row moves to the end of its table, and the id range read
// came back in that order; its callers merge by ascending id, so `tiles build` said a vertex was
// missing. Every third vertex is rewritten unchanged here to move it (a no-op on SQLite's rowid
// order), and the range must still ascend.
TEST_F(MeshTablesTest, IdRangeAscendsAfterRowsWereRewritten) {
  ASSERT_TRUE(store_->db().Exec("UPDATE vertices SET z = z WHERE id % 3 = 0").ok());
  MeshTables terrain(store_->db(), terrain_);
  const auto all = Vertices(terrain);
  ASSERT_GT(all.size(), 10u);
  const auto range = ReadAll<VertexCursor, VertexRow>(
      terrain.VerticesInIdRange(all.front().first, all.back().first));
  ASSERT_EQ(range.size(), all.size());
  for (size_t k = 1; k < range.size(); ++k)
    EXPECT_LT(range[k - 1].first, range[k].first) << "at " << k;
}

TEST_F(MeshTablesTest, MissingRowsAreNotFoundAndLinkedOnesCorruption) {
  MeshTables terrain(store_->db(), terrain_), other(store_->db(), other_);
  const auto triangles = Triangles(terrain);
  const auto vertices = Vertices(terrain);
  const int64_t triangle = triangles.front().first, vertex = vertices.front().first;

  // A row of another surface is not found through this one, nor is an id beyond every row.
  auto wrong = other.Triangle(triangle);
  ASSERT_FALSE(wrong.ok());
  EXPECT_EQ(wrong.status().code(), StatusCode::kNotFound);
  EXPECT_NE(wrong.status().message().find("'other'"), std::string::npos);
  EXPECT_NE(wrong.status().message().find(std::to_string(triangle)), std::string::npos);
  EXPECT_EQ(terrain.Triangle(int64_t{1} << 40).status().code(), StatusCode::kNotFound);
  EXPECT_FALSE(*other.HasTriangle(triangle));
  auto wrong_vertex = other.Vertex(vertex);
  ASSERT_FALSE(wrong_vertex.ok());
  EXPECT_EQ(wrong_vertex.status().code(), StatusCode::kNotFound);
  EXPECT_EQ(terrain.TagValue(int64_t{1} << 40).status().code(), StatusCode::kNotFound);

  // A cache that follows a link to a row that is gone says Corruption (the link is wrong).
  MeshCache cache(*store_, other_);
  auto linked = cache.Triangle(triangle);
  ASSERT_FALSE(linked.ok());
  EXPECT_EQ(linked.status().code(), StatusCode::kCorruption);
  EXPECT_EQ(cache.Vertex(vertex).status().code(), StatusCode::kCorruption);
}

TEST_F(MeshTablesTest, DeleteAllLeavesOtherSurfaces) {
  MeshTables terrain(store_->db(), terrain_), other(store_->db(), other_);
  const auto other_before = Vertices(other);
  {
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    ASSERT_TRUE(terrain.DeleteAll().ok());
    ASSERT_TRUE((*tx)->Commit().ok());
  }
  auto counts = terrain.Count();
  ASSERT_TRUE(counts.ok());
  EXPECT_EQ(counts->vertices, 0);
  EXPECT_EQ(counts->triangles, 0);
  EXPECT_EQ(counts->constraints, 0);
  EXPECT_TRUE(Triangles(terrain).empty());
  auto any = terrain.AnyTriangle();
  ASSERT_TRUE(any.ok());
  EXPECT_FALSE(any->has_value());
  const auto other_after = Vertices(other);
  ASSERT_EQ(other_after.size(), other_before.size());
  for (size_t k = 0; k < other_after.size(); ++k)
    EXPECT_EQ(other_after[k].first, other_before[k].first);
}

// Batches written as a triangulating thread hands them over, the links of earlier rows filled
// in by later batches, give the same surface as one write of the Tin.
TEST_F(MeshTablesTest, TriangleBatchesFillInLateLinks) {
  const Tin tin = testing::PerturbedGridTin(9, 9, 4);
  const size_t half = tin.triangles.size() / 2;
  SurfaceInfo spec;
  spec.name = "batched";
  spec.kind = SurfaceKind::kFree;  // a perturbed grid is not Delaunay
  spec.method = "test";
  auto tx = store_->BeginWrite();
  ASSERT_TRUE(tx.ok());
  size_t links = 0;
  auto info = SurfaceStore(*store_).CreateWhileTriangulating(
      spec, tin.vertices, [&](const TriangleOrder& order, const TriangleSink& finished) {
        for (size_t first : {size_t{0}, half}) {
          TriangleBatch batch;
          batch.first = first;
          const size_t end = first == 0 ? half : tin.triangles.size();
          for (size_t t = first; t < end; ++t) {
            TinTriangle tri = tin.triangles[t];
            for (int i = 0; i < 3; ++i) {
              const int32_t n = tri.n[i];
              if (n == kNoNeighbour || static_cast<size_t>(n) < end) continue;
              tri.n[i] = kNoNeighbour;  // not handed over yet: a later batch links it
            }
            batch.triangles.push_back(tri);
            batch.keys.push_back(order(tri));
          }
          if (first == half) {
            for (size_t t = 0; t < half; ++t)
              for (int i = 0; i < 3; ++i)
                if (tin.triangles[t].n[i] != kNoNeighbour &&
                    static_cast<size_t>(tin.triangles[t].n[i]) >= half) {
                  batch.links.push_back({static_cast<uint32_t>(t), i, tin.triangles[t].n[i]});
                  ++links;
                }
          }
          finished(std::move(batch));
        }
        return Status::Ok();
      });
  ASSERT_TRUE(info.ok()) << info.status().ToString();
  ASSERT_TRUE((*tx)->Commit().ok());
  EXPECT_GT(links, 0u);
  MeshTables tables(store_->db(), *info);
  const auto triangles = Triangles(tables);
  ASSERT_EQ(triangles.size(), tin.triangles.size());
  size_t linked = 0;
  for (const auto& [id, row] : triangles)
    for (const auto& n : row.n) linked += n.has_value();
  size_t expected = 0;
  for (const TinTriangle& t : tin.triangles)
    for (int32_t n : t.n) expected += n != kNoNeighbour;
  EXPECT_EQ(linked, expected);
  ExpectStoreIntact(*store_);
}

}  // namespace
}  // namespace tinbase
