// FindConflictRegion on a greedy surface of the Hamersley DEM: a new ring's region is exactly
// the triangles its segments meet and those whose circumcircle holds a new point (checked
// against a brute-force scan of every triangle); a ring along stored constraints seeds no
// region; a removal seeds the stars of its vertices and drops its ring vertices; a point off
// the surface is named.
#include "db/edit/conflict_region.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <vector>

#include "core/geometry/triangle_tests.h"
#include "db/polygon_editor.h"
#include "tests/support/edit_fixture.h"

namespace tinbase {
namespace {

using testing::kEditCell;
using testing::kEditCx;
using testing::kEditCy;
using testing::Ngon;
using testing::PointList;

class ConflictRegionTest : public testing::EditFixture {
 protected:
  // The stored triangles: store id -> corners (counter-clockwise).
  std::map<int64_t, TriangleCorners> AllTriangles() {
    std::map<int64_t, TriangleCorners> all;
    auto loaded = SurfaceStore(*store_).Load(surface_);
    EXPECT_TRUE(loaded.ok());
    if (!loaded.ok()) return all;
    for (size_t t = 0; t < loaded->tin.triangles.size(); ++t) {
      TriangleCorners c;
      for (int i = 0; i < 3; ++i) {
        const TinVertex& v = loaded->tin.vertices[loaded->tin.triangles[t].v[i]];
        c[i] = {v.x, v.y};
      }
      all[loaded->triangle_ids[t]] = c;
    }
    return all;
  }

  // Adds `ring` as a fill feature through the polygon editor; its id.
  int64_t Store(const PointList& ring) {
    PolygonAddOptions o;
    o.surface = "terrain";
    o.file = testing::WritePolygons(dir_, "stored.geojson", {{ring}});
    o.mode = FeatureMode::kFill;
    o.tag = "t";
    auto report = AddPolygons(*store_, o);
    EXPECT_TRUE(report.ok()) << report.status().ToString();
    EXPECT_TRUE(ReloadSurface());
    return report.ok() ? report->first_feature_id : 0;
  }

  // The constrained edges of `feature`, as stored.
  std::vector<MeshEdge> EdgesOf(int64_t feature) {
    auto edges = mesh_->EdgesOf(feature);
    EXPECT_TRUE(edges.ok());
    return edges.ok() ? *edges : std::vector<MeshEdge>{};
  }
};

TEST_F(ConflictRegionTest, NewRingTakesTheTrianglesItMeetsAndTheirCavity) {
  const LocalEdit edit = AddRing(Ngon(kEditCx, kEditCy, 5 * kEditCell, 14), 7);
  auto region = FindConflictRegion(Context(), edit);
  ASSERT_TRUE(region.ok()) << region.status().ToString();
  EXPECT_FALSE(region->whole_surface);
  EXPECT_TRUE(region->removed_edges.empty());
  EXPECT_TRUE(region->present.empty());
  ASSERT_EQ(region->lines.size(), 1u);
  const std::vector<TinVertex>& points = region->lines[0].points;
  ASSERT_GE(points.size(), 14u);
  std::vector<Point2> sorted;
  for (const TinVertex& p : points) sorted.push_back({p.x, p.y});
  std::sort(sorted.begin(), sorted.end(),
            [](const Point2& a, const Point2& b) { return a.x < b.x; });

  const auto all = AllTriangles();
  size_t met = 0;
  for (const auto& [id, c] : all) {
    bool meets = false;
    for (size_t k = 0; k < points.size() && !meets; ++k) {
      const TinVertex& p = points[k];
      const TinVertex& q = points[(k + 1) % points.size()];
      meets = SegmentMeetsTriangle({p.x, p.y}, {q.x, q.y}, c[0], c[1], c[2]);
    }
    met += meets;
    if (meets) {
      EXPECT_TRUE(region->Has(id)) << "triangle " << id << " meets the ring but is not in R";
    } else if (region->Has(id)) {
      EXPECT_TRUE(CircleHoldsAny(c, sorted))
          << "triangle " << id << " is in R without meeting the ring or holding a new point";
    }
  }
  EXPECT_GT(met, 14u);
  EXPECT_GT(region->triangles.size(), met);  // the cavity reaches beyond the ring's triangles
  EXPECT_LT(region->triangles.size(), all.size() / 2);
  EXPECT_EQ(region->members.size(), region->triangles.size());
}

TEST_F(ConflictRegionTest, RingAlongStoredConstraintsSeedsNothing) {
  const PointList ring = Ngon(kEditCx, kEditCy, 4 * kEditCell, 11);
  const int64_t stored = Store(ring);
  // The stored ring's vertices in order around it: every new segment is a stored constraint.
  const std::vector<MeshEdge> edges = EdgesOf(stored);
  ASSERT_GE(edges.size(), 11u);
  std::map<int64_t, std::vector<int64_t>> next;
  for (const auto& [a, b] : edges) next[a].push_back(b), next[b].push_back(a);
  std::vector<int64_t> cycle{edges.front().first};
  for (int64_t previous = 0; cycle.size() < edges.size();) {
    const std::vector<int64_t>& n = next[cycle.back()];
    ASSERT_EQ(n.size(), 2u);
    const int64_t go = n[0] != previous ? n[0] : n[1];
    previous = cycle.back();
    cycle.push_back(go);
  }
  PointList along;
  for (int64_t v : cycle) {
    auto p = mesh_->At(v);
    ASSERT_TRUE(p.ok());
    along.push_back({p->x, p->y});
  }
  along.push_back(along.front());
  LocalEdit edit = AddRing(along, 99);

  auto region = FindConflictRegion(Context(), edit);
  ASSERT_TRUE(region.ok()) << region.status().ToString();
  EXPECT_TRUE(region->triangles.empty());
  EXPECT_TRUE(region->lines.empty());
  ASSERT_EQ(region->present.size(), edges.size());
  for (const MeshEdge& e : edges) {
    ASSERT_TRUE(region->present.count(e)) << e.first << "-" << e.second;
    EXPECT_EQ(region->present.at(e), std::vector<int64_t>{99});
  }
}

TEST_F(ConflictRegionTest, RemovalSeedsTheStarsAndDropsTheRingVertices) {
  const int64_t stored = Store(Ngon(kEditCx, kEditCy, 4 * kEditCell, 11));
  const std::vector<MeshEdge> edges = EdgesOf(stored);
  std::set<int64_t> ring_vertices;
  for (const auto& [a, b] : edges) ring_vertices.insert(a), ring_vertices.insert(b);
  LocalEdit edit;
  edit.remove = {stored};

  auto region = FindConflictRegion(Context(), edit);
  ASSERT_TRUE(region.ok()) << region.status().ToString();
  EXPECT_EQ(region->removed_edges, std::set<MeshEdge>(edges.begin(), edges.end()));
  ASSERT_EQ(region->removed_features.size(), 1u);
  EXPECT_EQ(region->removed_features[0].id, stored);
  EXPECT_EQ(region->restore, nullptr);  // a fill, not a replace
  size_t ring_kind = 0;
  for (int64_t v : ring_vertices) {
    auto vertex = mesh_->Vertex(v);
    ASSERT_TRUE(vertex.ok());
    if ((*vertex)->kind == VertexKind::kRing) {
      ++ring_kind;
      EXPECT_TRUE(region->dropped.count(v)) << "ring vertex " << v << " stays";
    }
  }
  EXPECT_GT(ring_kind, 0u);
  EXPECT_EQ(region->dropped.size(), ring_kind);
  for (const auto& [id, c] : AllTriangles()) {
    auto tri = mesh_->Triangle(id);
    ASSERT_TRUE(tri.ok());
    const bool on_ring = std::any_of((*tri)->v.begin(), (*tri)->v.end(),
                                     [&](int64_t v) { return ring_vertices.count(v) > 0; });
    EXPECT_EQ(region->Has(id), on_ring) << "triangle " << id;
  }
}

TEST_F(ConflictRegionTest, PointOffTheSurfaceIsNamed) {
  const LocalEdit edit = AddRing(Ngon(kEditCx + 1e6, kEditCy, 2 * kEditCell, 5), 7);
  auto region = FindConflictRegion(Context(), edit);
  ASSERT_EQ(region.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(region.status().message().find("feature 7, point 0"), std::string::npos)
      << region.status().ToString();
  EXPECT_NE(region.status().message().find("outside surface 'terrain'"), std::string::npos)
      << region.status().ToString();
}

}  // namespace
}  // namespace tinbase
