// StarOf and NeighboursOf on a hand-built hexagon whose stars and neighbours are known, and on a
// random Delaunay TIN against brute force over every triangle.
#include "db/query/topology.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "tests/db/query/query_fixture.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::TempDir;

// Vertex 0 at the centre, 1..6 around it counter-clockwise from east; triangle k-1 is
// (0, k, k % 6 + 1). The spoke 0-1 is constrained.
Tin Hexagon() {
  Tin tin;
  tin.vertices.push_back({0, 0, 10, VertexKind::kUser});
  for (int k = 0; k < 6; ++k) {
    const double a = k * M_PI / 3;
    tin.vertices.push_back(
        {100 * std::cos(a), 100 * std::sin(a), static_cast<double>(k), VertexKind::kUser});
  }
  for (uint32_t k = 1; k <= 6; ++k) tin.triangles.push_back({{0, k, k % 6 + 1}});
  EXPECT_TRUE(LinkNeighbours(tin));
  tin.constraints.push_back({0, 1});
  return tin;
}

// Store ids by the input's vertex and triangle positions, matched by coordinates (the store
// numbers vertices in its own order).
struct Ids {
  std::vector<int64_t> vertex;
  std::map<std::set<int64_t>, int64_t> triangle;  // by corner ids
};
Ids IdsOf(const Tin& input, const LoadedSurface& s) {
  Ids ids;
  for (const TinVertex& v : input.vertices)
    for (size_t i = 0; i < s.tin.vertices.size(); ++i)
      if (s.tin.vertices[i].x == v.x && s.tin.vertices[i].y == v.y)
        ids.vertex.push_back(s.vertex_ids[i]);
  for (size_t t = 0; t < s.tin.triangles.size(); ++t) {
    std::set<int64_t> corners;
    for (uint32_t v : s.tin.triangles[t].v) corners.insert(s.vertex_ids[v]);
    ids.triangle[corners] = s.triangle_ids[t];
  }
  return ids;
}

class HexagonTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto stored = testing::StoreSurface(testing::StoreTarget(dir_, "h.tinbase"), "hex", Hexagon());
    ASSERT_TRUE(stored.ok()) << stored.status().ToString();
    s_ = std::move(*stored);
    ids_ = IdsOf(Hexagon(), s_.loaded);
    ASSERT_EQ(ids_.vertex.size(), 7u);
  }
  int64_t V(int k) const { return ids_.vertex[static_cast<size_t>(k)]; }
  int64_t T(int a, int b, int c) const { return ids_.triangle.at({V(a), V(b), V(c)}); }

  TempDir dir_;
  testing::StoredSurface s_;
  Ids ids_;
};

TEST_F(HexagonTest, TheCentreIsSurroundedByTheRingCounterClockwise) {
  auto star = StarOf(*s_.store, s_.info, V(0));
  ASSERT_TRUE(star.ok()) << star.status().ToString();
  EXPECT_FALSE(star->boundary);
  EXPECT_EQ(star->row.z, 10);
  ASSERT_EQ(star->triangles.size(), 6u);
  ASSERT_EQ(star->links.size(), 6u);
  // The ring from wherever the walk entered it, counter-clockwise.
  const auto first = std::find(ids_.vertex.begin() + 1, ids_.vertex.end(), star->links[0]);
  ASSERT_NE(first, ids_.vertex.end());
  const int k0 = static_cast<int>(first - ids_.vertex.begin());
  for (int i = 0; i < 6; ++i) {
    const int k = (k0 - 1 + i) % 6 + 1;
    EXPECT_EQ(star->links[i], V(k)) << i;
    EXPECT_EQ(star->triangles[i], T(0, k, k % 6 + 1)) << i;
  }
}

TEST_F(HexagonTest, ARingVertexIsOnTheBoundaryWithTwoTriangles) {
  auto star = StarOf(*s_.store, s_.info, V(1));
  ASSERT_TRUE(star.ok()) << star.status().ToString();
  EXPECT_TRUE(star->boundary);
  // Around (100, 0) counter-clockwise: vertex 2 (up-left), the centre (west), 6 (down-left).
  EXPECT_EQ(star->links, (std::vector<int64_t>{V(2), V(0), V(6)}));
  EXPECT_EQ(star->triangles, (std::vector<int64_t>{T(0, 1, 2), T(0, 6, 1)}));
}

TEST_F(HexagonTest, NeighboursNameTheSharedEdgesAndTheConstraint) {
  auto nb = NeighboursOf(*s_.store, s_.info, T(0, 1, 2));
  ASSERT_TRUE(nb.ok()) << nb.status().ToString();
  int boundary = 0;
  for (int i = 0; i < 3; ++i) {
    const SharedEdge& e = nb->edges[i];
    // The edge is the one opposite corner i, in the triangle's order.
    EXPECT_EQ(e.vertices[0], nb->row.v[(i + 1) % 3]);
    EXPECT_EQ(e.vertices[1], nb->row.v[(i + 2) % 3]);
    const std::set<int64_t> edge{e.vertices[0], e.vertices[1]};
    if (edge == std::set<int64_t>{V(1), V(2)}) {
      EXPECT_FALSE(e.neighbour.has_value());
      ++boundary;
    } else if (edge == std::set<int64_t>{V(0), V(1)}) {
      EXPECT_EQ(e.neighbour, T(0, 6, 1));
      EXPECT_TRUE(e.constrained);
    } else {
      EXPECT_EQ(edge, (std::set<int64_t>{V(0), V(2)}));
      EXPECT_EQ(e.neighbour, T(0, 2, 3));
      EXPECT_FALSE(e.constrained);
    }
    for (int end = 0; end < 2; ++end) {
      const int k = static_cast<int>(
          std::find(ids_.vertex.begin(), ids_.vertex.end(), e.vertices[end]) - ids_.vertex.begin());
      EXPECT_EQ(e.ends[end].z, k == 0 ? 10 : k - 1) << "vertex " << k;  // Hexagon()'s heights
    }
  }
  EXPECT_EQ(boundary, 1);
}

TEST_F(HexagonTest, UnknownVerticesAndTrianglesAreNotFound) {
  auto star = StarOf(*s_.store, s_.info, 999999);
  ASSERT_FALSE(star.ok());
  EXPECT_EQ(star.status().code(), StatusCode::kNotFound);
  EXPECT_NE(star.status().message().find("999999"), std::string::npos);
  auto nb = NeighboursOf(*s_.store, s_.info, 888888);
  ASSERT_FALSE(nb.ok());
  EXPECT_EQ(nb.status().code(), StatusCode::kNotFound);
  EXPECT_NE(nb.status().message().find("888888"), std::string::npos);
}

// On a random Delaunay TIN, every vertex's star is exactly the triangles that have it, each
// consecutive pair sharing the spoke between them, and it is on the boundary exactly when one
// of its spokes has a triangle on one side only.
TEST(Topology, StarsOfARandomTinAgreeWithBruteForce) {
  TempDir dir;
  testing::RandomTinOptions options;
  options.points = 300;
  options.seed = 11;
  auto stored = testing::StoreSurface(testing::StoreTarget(dir, "r.tinbase"), "r",
                                      testing::RandomDelaunayTin(options));
  ASSERT_TRUE(stored.ok()) << stored.status().ToString();
  const LoadedSurface& s = stored->loaded;
  std::map<int64_t, std::set<int64_t>> around;
  std::map<int64_t, bool> on_boundary;
  for (size_t t = 0; t < s.tin.triangles.size(); ++t) {
    const TinTriangle& tri = s.tin.triangles[t];
    for (int i = 0; i < 3; ++i) {
      around[s.vertex_ids[tri.v[i]]].insert(s.triangle_ids[t]);
      if (tri.n[i] == kNoNeighbour) {
        on_boundary[s.vertex_ids[tri.v[(i + 1) % 3]]] = true;
        on_boundary[s.vertex_ids[tri.v[(i + 2) % 3]]] = true;
      }
    }
  }
  for (const auto& [vertex, triangles] : around) {
    auto star = StarOf(*stored->store, stored->info, vertex);
    ASSERT_TRUE(star.ok()) << star.status().ToString();
    EXPECT_EQ(std::set<int64_t>(star->triangles.begin(), star->triangles.end()), triangles)
        << "vertex " << vertex;
    EXPECT_EQ(star->triangles.size(), triangles.size());
    EXPECT_EQ(star->boundary, on_boundary[vertex]) << "vertex " << vertex;
    EXPECT_EQ(star->links.size(), triangles.size() + (star->boundary ? 1 : 0));
  }
}

}  // namespace
}  // namespace tinbase
