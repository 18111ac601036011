// CheckStore passes intact stores and reports each deliberate corruption with its exact code on
// the triangle it concerns (as sqlite's rtreecheck.test and LevelDB's corruption_test do).
#include "db/integrity_check.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <set>

#include "core/geometry/predicates.h"
#include "db/surface_store.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::StoreTarget;
using testing::TempDir;

class IntegrityCheckTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = Store::Create(StoreTarget(dir_, "s.tinbase"), "EPSG:32632");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    terrain_ = Create("terrain", SurfaceKind::kDelaunay,
                      testing::RandomDelaunayTin({.points = 2000, .seed = 21, .ring = true}));
    rtin_ = Create("rtin", SurfaceKind::kFree, testing::PerturbedGridTin(30, 30, 22));
    ASSERT_TRUE((*tx)->Commit().ok());
    auto loaded = SurfaceStore(*store_).Load(terrain_);
    ASSERT_TRUE(loaded.ok());
    loaded_ = std::move(*loaded);
  }

  SurfaceInfo Create(const std::string& name, SurfaceKind kind, const Tin& tin) {
    SurfaceInfo spec;
    spec.name = name;
    spec.kind = kind;
    spec.method = "test";
    auto info = SurfaceStore(*store_).Create(spec, tin);
    EXPECT_TRUE(info.ok()) << info.status().ToString();
    return info.ok() ? *info : SurfaceInfo{};
  }

  void Sql(const std::string& sql) { ASSERT_TRUE(store_->db().Exec(sql).ok()) << sql; }
  int64_t Int(const std::string& sql) {
    auto v = store_->db().QueryInt(sql);
    EXPECT_TRUE(v.ok()) << sql;
    return v.ok() ? *v : -1;
  }

  std::vector<Problem> Check(const CheckOptions& options = {}) {
    auto problems = CheckStore(*store_, options);
    EXPECT_TRUE(problems.ok()) << problems.status().ToString();
    return problems.ok() ? *problems : std::vector<Problem>{};
  }

  // The first problem; fails the test when there is none.
  Problem First() {
    const std::vector<Problem> problems = Check();
    EXPECT_FALSE(problems.empty());
    return problems.empty() ? Problem{} : problems.front();
  }

  std::string Id(int64_t id) { return std::to_string(id); }

  // The store id of terrain's i-th triangle and its neighbour across edge k.
  int64_t TriangleId(size_t t) const { return loaded_.triangle_ids[t]; }
  int64_t VertexId(uint32_t v) const { return loaded_.vertex_ids[v]; }

  // Index of the lowest-id triangle of terrain with three neighbours.
  size_t InteriorTriangle() const {
    for (size_t t = 0; t < loaded_.tin.triangles.size(); ++t) {
      const auto& n = loaded_.tin.triangles[t].n;
      if (std::count(n.begin(), n.end(), kNoNeighbour) == 0) return t;
    }
    ADD_FAILURE() << "no interior triangle";
    return 0;
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
  SurfaceInfo terrain_, rtin_;
  LoadedSurface loaded_;
};

TEST_F(IntegrityCheckTest, IntactStoreHasNoProblems) {
  ASSERT_FALSE(loaded_.tin.constraints.empty());
  testing::ExpectStoreIntact(*store_);
  EXPECT_TRUE(Check({.surface = "rtin"}).empty());
}

TEST_F(IntegrityCheckTest, UnknownSurfaceIsNotFound) {
  auto problems = CheckStore(*store_, {.surface = "nowhere"});
  ASSERT_FALSE(problems.ok());
  EXPECT_EQ(problems.status().code(), StatusCode::kNotFound);
}

TEST_F(IntegrityCheckTest, FreeSurfacesAreExemptFromDelaunay) {
  // The same random-diagonal grid stored as a Delaunay surface breaks invariant 5 on some edges.
  auto tx = store_->BeginWrite();
  ASSERT_TRUE(tx.ok());
  const SurfaceInfo strict =
      Create("strict", SurfaceKind::kDelaunay, testing::PerturbedGridTin(30, 30, 22));
  ASSERT_TRUE((*tx)->Commit().ok());
  const std::vector<Problem> problems = Check();
  ASSERT_FALSE(problems.empty());
  for (const Problem& p : problems) {
    EXPECT_EQ(p.code, "not-delaunay") << p.message;
    EXPECT_EQ(p.surface, strict.id);
  }
  EXPECT_TRUE(
      std::is_sorted(problems.begin(), problems.end(),
                     [](const Problem& a, const Problem& b) { return a.triangle < b.triangle; }));
}

TEST_F(IntegrityCheckTest, CoCircularGridIsDelaunayWhicheverDiagonal) {
  // Every cell of a regular grid has four co-circular corners: either diagonal is a tie, which
  // invariant 5 allows (docs/design.md, Pitfalls).
  auto tx = store_->BeginWrite();
  ASSERT_TRUE(tx.ok());
  Create("grid", SurfaceKind::kDelaunay, testing::PerturbedGridTin(40, 30, 23, 30, 0.0));
  ASSERT_TRUE((*tx)->Commit().ok());
  testing::ExpectStoreIntact(*store_);
}

TEST_F(IntegrityCheckTest, FlippedTriangleIsClockwise) {
  const int64_t t = TriangleId(0);  // lowest id, so the broken links it causes come after
  Sql("UPDATE triangles SET v1 = v2, v2 = v1 WHERE id = " + Id(t));
  const Problem p = First();
  EXPECT_EQ(p.code, "clockwise-triangle");
  EXPECT_EQ(p.surface, terrain_.id);
  EXPECT_EQ(p.triangle, t);
  EXPECT_EQ(p.message, "surface 'terrain', triangle " + Id(t) + ": vertices are clockwise");
}

TEST_F(IntegrityCheckTest, CollinearTriangleIsDegenerate) {
  const size_t t = InteriorTriangle();
  const auto& v = loaded_.tin.triangles[t].v;
  // Move v0 onto the line through v1 and v2, beyond v2 so no other vertex is hit: exactly on
  // it, since v2 + (v2 - v1) rounds only in the last bits and the exact predicate judges it.
  const TinVertex &b = loaded_.tin.vertices[v[1]], &c = loaded_.tin.vertices[v[2]];
  Point2 on{c.x + (c.x - b.x), c.y + (c.y - b.y)};
  if (Orientation({b.x, b.y}, {c.x, c.y}, on) != 0) on = {c.x, c.y};  // fall back: coincide
  auto update = store_->db().Prepare("UPDATE vertices SET x = ?, y = ? WHERE id = ?");
  ASSERT_TRUE(update.ok());
  ASSERT_TRUE((*update)->Bind(1, on.x).Bind(2, on.y).Bind(3, VertexId(v[0])).Run().ok());
  const std::vector<Problem> problems = Check();
  EXPECT_TRUE(std::any_of(problems.begin(), problems.end(), [&](const Problem& p) {
    return p.code == "degenerate-triangle" && p.triangle == TriangleId(t);
  }));
}

TEST_F(IntegrityCheckTest, LinkToAForeignTriangleIsAnEdgeMismatch) {
  const size_t t = InteriorTriangle();
  const int64_t id = TriangleId(t);
  const int64_t real = TriangleId(loaded_.tin.triangles[t].n[0]);
  const int64_t foreign = loaded_.triangle_ids.back();
  ASSERT_NE(real, foreign);
  Sql("UPDATE triangles SET n0 = " + Id(foreign) + " WHERE id = " + Id(id));
  const std::vector<Problem> problems = Check();
  ASSERT_FALSE(problems.empty());
  EXPECT_EQ(problems[0].code, "neighbour-edge-mismatch");
  EXPECT_EQ(problems[0].triangle, id);
  // The real neighbour still names this triangle, which no longer names it back.
  EXPECT_TRUE(std::any_of(problems.begin(), problems.end(), [&](const Problem& p) {
    return p.code == "asymmetric-neighbour" && p.triangle == real;
  }));
}

TEST_F(IntegrityCheckTest, LinkToNoTriangleIsABadNeighbour) {
  const int64_t id = TriangleId(InteriorTriangle());
  Sql("UPDATE triangles SET n2 = 987654321 WHERE id = " + Id(id));
  const Problem p = First();
  EXPECT_EQ(p.code, "bad-neighbour");
  EXPECT_EQ(p.triangle, id);
}

TEST_F(IntegrityCheckTest, ClearedLinkIsAMissingNeighbour) {
  const int64_t id = TriangleId(InteriorTriangle());
  Sql("UPDATE triangles SET n1 = NULL WHERE id = " + Id(id));
  const Problem p = First();
  EXPECT_EQ(p.code, "missing-neighbour");
  EXPECT_EQ(p.triangle, id);
}

TEST_F(IntegrityCheckTest, DeletedTriangleLeavesBadNeighbours) {
  const size_t t = loaded_.tin.triangles.size() / 2;
  const auto& n = loaded_.tin.triangles[t].n;
  int64_t lowest = INT64_MAX;
  for (int32_t u : n) {
    if (u != kNoNeighbour) lowest = std::min(lowest, TriangleId(u));
  }
  ASSERT_NE(lowest, INT64_MAX);
  Sql("DELETE FROM triangles WHERE id = " + Id(TriangleId(t)));
  const std::vector<Problem> problems = Check();
  ASSERT_FALSE(problems.empty());
  EXPECT_EQ(problems[0].code, "bad-neighbour");
  EXPECT_EQ(problems[0].triangle, lowest);
  // A hole is a valid domain: Euler's formula still holds with one more boundary loop.
  for (const Problem& p : problems) EXPECT_NE(p.code, "euler") << p.message;
}

TEST_F(IntegrityCheckTest, DeletedVertexIsMissing) {
  // A DEM vertex of the middle triangle; the first triangle using it is reported.
  const size_t t = loaded_.tin.triangles.size() / 2;
  const uint32_t v = loaded_.tin.triangles[t].v[0];
  ASSERT_EQ(loaded_.tin.vertices[v].kind, VertexKind::kDem);
  int64_t first_user = INT64_MAX;
  for (size_t u = 0; u < loaded_.tin.triangles.size(); ++u) {
    const auto& vs = loaded_.tin.triangles[u].v;
    if (std::find(vs.begin(), vs.end(), v) != vs.end())
      first_user = std::min(first_user, TriangleId(u));
  }
  Sql("DELETE FROM vertices WHERE id = " + Id(VertexId(v)));
  const Problem p = First();
  EXPECT_EQ(p.code, "vertex-missing");
  EXPECT_EQ(p.triangle, first_user);
  EXPECT_NE(p.message.find("vertex " + Id(VertexId(v))), std::string::npos) << p.message;
}

TEST_F(IntegrityCheckTest, DuplicatedVertexPositionIsReported) {
  const int64_t a = VertexId(10), b = VertexId(20);
  Sql("UPDATE vertices SET x = (SELECT x FROM vertices WHERE id = " + Id(a) +
      "), y = (SELECT y FROM vertices WHERE id = " + Id(a) + ") WHERE id = " + Id(b));
  const Problem p = First();
  EXPECT_EQ(p.code, "duplicate-vertex");
  EXPECT_EQ(p.triangle, std::nullopt);
  EXPECT_EQ(p.message, "surface 'terrain': vertices " + Id(a) + " and " + Id(b) + " share x, y");
}

TEST_F(IntegrityCheckTest, ConstraintThatIsNotAnEdge) {
  // Two vertices far apart (first and last by position in the random fixture) share no edge.
  std::set<std::pair<uint32_t, uint32_t>> edges;
  for (const TinTriangle& tri : loaded_.tin.triangles) {
    for (int i = 0; i < 3; ++i) {
      edges.emplace(std::min(tri.v[i], tri.v[(i + 1) % 3]), std::max(tri.v[i], tri.v[(i + 1) % 3]));
    }
  }
  uint32_t a = 0, b = 1;
  while (edges.count({a, b})) ++b;
  Sql("INSERT INTO constraints(surface, va, vb) VALUES (" + Id(terrain_.id) + ", " +
      Id(VertexId(a)) + ", " + Id(VertexId(b)) + ")");
  const Problem p = First();
  EXPECT_EQ(p.code, "constraint-not-edge");
  EXPECT_EQ(p.triangle, std::nullopt);
  EXPECT_NE(p.message.find("(" + Id(VertexId(a)) + ", " + Id(VertexId(b)) + ")"),
            std::string::npos);
}

TEST_F(IntegrityCheckTest, OrphanVertexBreaksEuler) {
  Sql("INSERT INTO vertices(surface, x, y, z, kind) VALUES (" + Id(terrain_.id) +
      ", 1, 2, 3, 'user')");
  const int64_t orphan = *store_->db().QueryInt("SELECT max(id) FROM vertices");
  const Problem p = First();
  EXPECT_EQ(p.code, "euler");
  EXPECT_EQ(p.triangle, std::nullopt);
  EXPECT_EQ(p.message, "surface 'terrain': vertex " + Id(orphan) + " is used by no triangle");
}

TEST_F(IntegrityCheckTest, CopiedTriangleOverusesEdgesAndOverlaps) {
  const int64_t t = TriangleId(InteriorTriangle());
  Sql("INSERT INTO triangles(surface, v0, v1, v2, n0, n1, n2, block) "
      "SELECT surface, v0, v1, v2, n0, n1, n2, block FROM triangles WHERE id = " +
      Id(t));
  const int64_t copy = *store_->db().QueryInt("SELECT max(id) FROM triangles");
  const std::vector<Problem> problems = Check();
  auto first_on_copy = std::find_if(problems.begin(), problems.end(),
                                    [&](const Problem& p) { return p.triangle == copy; });
  ASSERT_NE(first_on_copy, problems.end());
  EXPECT_EQ(first_on_copy->code, "overused-edge");
  // Its corners are now wound twice: the fans overlap.
  EXPECT_TRUE(std::any_of(problems.begin(), problems.end(),
                          [](const Problem& p) { return p.code == "overlap"; }));
}

TEST_F(IntegrityCheckTest, MovedVertexBreaksDelaunay) {
  // Find an unconstrained interior edge (a, b) of triangle t whose far vertex d (in neighbour u)
  // can be pulled towards the edge until it enters t's circumcircle while every triangle around
  // d stays counter-clockwise.
  Tin tin = loaded_.tin;
  std::set<std::pair<uint32_t, uint32_t>> constrained;
  for (auto [a, b] : tin.constraints) constrained.emplace(std::min(a, b), std::max(a, b));
  const auto point = [&](uint32_t v) { return Point2{tin.vertices[v].x, tin.vertices[v].y}; };
  const auto fan_stays_ccw = [&](uint32_t d, const Point2& moved) {
    for (const TinTriangle& tri : tin.triangles) {
      std::array<Point2, 3> p{point(tri.v[0]), point(tri.v[1]), point(tri.v[2])};
      bool touches = false;
      for (int i = 0; i < 3; ++i) {
        if (tri.v[i] == d) p[i] = moved, touches = true;
      }
      if (touches && Orientation(p[0], p[1], p[2]) <= 0) return false;
    }
    return true;
  };
  std::optional<std::pair<uint32_t, Point2>> move;
  for (size_t t = 0; t < tin.triangles.size() && !move; ++t) {
    const TinTriangle& tri = tin.triangles[t];
    for (int i = 0; i < 3 && !move; ++i) {
      const uint32_t a = tri.v[(i + 1) % 3], b = tri.v[(i + 2) % 3];
      if (tri.n[i] == kNoNeighbour || constrained.count({std::min(a, b), std::max(a, b)})) continue;
      const TinTriangle& u = tin.triangles[tri.n[i]];
      uint32_t d = u.v[0];
      for (uint32_t v : u.v) {
        if (v != a && v != b) d = v;
      }
      if (tin.vertices[d].kind != VertexKind::kDem) continue;
      const Point2 m{(point(a).x + point(b).x) / 2, (point(a).y + point(b).y) / 2};
      for (double s : {0.3, 0.5, 0.7}) {
        const Point2 moved{point(d).x + s * (m.x - point(d).x),
                           point(d).y + s * (m.y - point(d).y)};
        if (InCircle(point(tri.v[0]), point(tri.v[1]), point(tri.v[2]), moved) > 0 &&
            fan_stays_ccw(d, moved)) {
          move = std::make_pair(d, moved);
          break;
        }
      }
    }
  }
  ASSERT_TRUE(move.has_value());
  const auto [d, moved] = *move;
  tin.vertices[d].x = moved.x;
  tin.vertices[d].y = moved.y;

  // Write the move with bound doubles, and the blocks of the triangles whose centroid moved.
  auto update = store_->db().Prepare("UPDATE vertices SET x = ?, y = ? WHERE id = ?");
  ASSERT_TRUE(update.ok());
  ASSERT_TRUE((*update)->Bind(1, moved.x).Bind(2, moved.y).Bind(3, VertexId(d)).Run().ok());
  auto block = store_->db().Prepare("UPDATE triangles SET block = ? WHERE id = ?");
  ASSERT_TRUE(block.ok());
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const auto& v = tin.triangles[t].v;
    if (std::find(v.begin(), v.end(), d) == v.end()) continue;
    const Point2 p0 = point(v[0]), p1 = point(v[1]), p2 = point(v[2]);
    const int64_t b = CentroidBlock(terrain_.blocks, p0.x, p0.y, p1.x, p1.y, p2.x, p2.y);
    ASSERT_TRUE((*block)->Bind(1, b).Bind(2, TriangleId(t)).Run().ok());
  }

  // Reference: every unconstrained interior edge whose far vertex is strictly inside, on the
  // lower id of its two triangles (ids grow with the index).
  std::vector<int64_t> expected;
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    for (int i = 0; i < 3; ++i) {
      const uint32_t a = tri.v[(i + 1) % 3], b = tri.v[(i + 2) % 3];
      if (tri.n[i] == kNoNeighbour || static_cast<size_t>(tri.n[i]) < t ||
          constrained.count({std::min(a, b), std::max(a, b)}))
        continue;
      for (uint32_t far : tin.triangles[tri.n[i]].v) {
        if (far != a && far != b &&
            InCircle(point(tri.v[0]), point(tri.v[1]), point(tri.v[2]), point(far)) > 0)
          expected.push_back(TriangleId(t));
      }
    }
  }
  ASSERT_FALSE(expected.empty());
  std::sort(expected.begin(), expected.end());
  std::vector<int64_t> reported;
  for (const Problem& p : Check()) {
    EXPECT_EQ(p.code, "not-delaunay") << p.message;
    reported.push_back(p.triangle.value_or(-1));
  }
  EXPECT_EQ(reported, expected);
}

TEST_F(IntegrityCheckTest, WrongBlockIsReported) {
  const int64_t t = TriangleId(loaded_.tin.triangles.size() / 3);
  const int64_t block = Int("SELECT block FROM triangles WHERE id = " + Id(t));
  Sql("UPDATE triangles SET block = block + 1 WHERE id = " + Id(t));
  const std::vector<Problem> problems = Check();
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].code, "wrong-block");
  EXPECT_EQ(problems[0].triangle, t);
  EXPECT_EQ(problems[0].message, "surface 'terrain', triangle " + Id(t) + ": block is " +
                                     Id(block + 1) + " but the centroid is in block " + Id(block));
}

// triangles.tag is not a declared foreign key (migration 0009): the check stands in for it.
TEST_F(IntegrityCheckTest, TagThatIsNotARowOfTagsIsUnknown) {
  const int64_t tagged = TriangleId(7), dangling = TriangleId(loaded_.tin.triangles.size() / 2);
  Sql("INSERT INTO tags(value) VALUES ('granite') ON CONFLICT DO NOTHING");
  const int64_t granite = Int("SELECT id FROM tags WHERE value = 'granite'");
  Sql("UPDATE triangles SET tag = " + Id(granite) + " WHERE id = " + Id(tagged));
  EXPECT_TRUE(Check().empty()) << "a tag that exists is not a problem";
  Sql("UPDATE triangles SET tag = " + Id(granite + 1000) + " WHERE id = " + Id(dangling));
  const std::vector<Problem> problems = Check();
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].code, "unknown-tag");
  EXPECT_EQ(problems[0].triangle, dangling);
  EXPECT_EQ(problems[0].message, "surface 'terrain', triangle " + Id(dangling) + ": tag " +
                                     Id(granite + 1000) + " is not a row of tags");
}

TEST_F(IntegrityCheckTest, ProblemsAreOrderedBySurfaceThenTriangle) {
  const int64_t late = TriangleId(loaded_.tin.triangles.size() - 1);
  const int64_t early = TriangleId(5);
  Sql("UPDATE triangles SET block = block + 1 WHERE id IN (" + Id(late) + ", " + Id(early) + ")");
  Sql("UPDATE triangles SET block = block + 1 WHERE id = (SELECT min(id) FROM triangles "
      "WHERE surface = " +
      Id(rtin_.id) + ")");
  const std::vector<Problem> problems = Check();
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_EQ(problems[0].triangle, early);
  EXPECT_EQ(problems[1].triangle, late);
  EXPECT_EQ(problems[2].surface, rtin_.id);
  EXPECT_EQ(Check({.surface = "rtin"}).size(), 1u);
}

// Property: whatever the seed and size, the fixtures' surfaces pass the check (a CDT also as a
// `delaunay` surface), so the checker raises no false alarms. RapidCheck prints the seed.
RC_GTEST_PROP(IntegrityCheckProperty, ValidSurfacesAreIntact, ()) {
  const auto seed = *rc::gen::arbitrary<uint32_t>();
  TempDir dir;
  auto store = Store::Create(StoreTarget(dir, "p.tinbase"), "");
  RC_ASSERT(store.ok());
  {
    auto tx = (*store)->BeginWrite();
    RC_ASSERT(tx.ok());
    SurfaceStore surfaces(**store);
    SurfaceInfo spec;
    spec.method = "test";
    spec.name = "cdt";
    const int points = *rc::gen::inRange(3, 400);
    const bool ring = *rc::gen::arbitrary<bool>();
    RC_ASSERT(surfaces
                  .Create(spec, testing::RandomDelaunayTin(
                                    {.points = points, .seed = seed, .ring = ring, .size = 700}))
                  .ok());
    spec.name = "grid";
    spec.kind = SurfaceKind::kFree;
    RC_ASSERT(surfaces
                  .Create(spec, testing::PerturbedGridTin(*rc::gen::inRange(2, 20),
                                                          *rc::gen::inRange(2, 20), seed))
                  .ok());
    RC_ASSERT((*tx)->Commit().ok());
  }
  auto problems = CheckStore(**store);
  RC_ASSERT(problems.ok());
  if (!problems->empty()) RC_FAIL(problems->front().message);
}

}  // namespace
}  // namespace tinbase
