// WalkLine on in-memory TINs with known answers: a plane whose z is analytic, lines across
// cells, along grid edges, through vertices, starting on a vertex and leaving the surface; and
// random lines over a free (non-Delaunay) TIN checked against brute force.
#include "core/query/line_walk.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/tin/tin.h"
#include "tests/support/grid_tin.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::MakeGridTin;

double Plane(double x, double y) { return 2 * x - 3 * y + 5; }

// Reads the triangles of `tin` with their indices as ids.
WalkTriangleReader ReaderOf(const Tin& tin, int* reads = nullptr) {
  return [&tin, reads](int64_t id) -> Result<WalkTriangle> {
    if (id < 0 || id >= static_cast<int64_t>(tin.triangles.size()))
      return Status::NotFound("no triangle " + std::to_string(id));
    if (reads != nullptr) ++*reads;
    const TinTriangle& t = tin.triangles[static_cast<size_t>(id)];
    WalkTriangle w;
    for (int i = 0; i < 3; ++i) {
      const TinVertex& v = tin.vertices[t.v[i]];
      w.v[i] = t.v[i];
      w.p[i] = {v.x, v.y};
      w.z[i] = v.z;
      if (t.n[i] != kNoNeighbour) w.n[i] = t.n[i];
    }
    return w;
  };
}

bool Holds(const Tin& tin, size_t t, const Point2& p) {
  const auto& v = tin.triangles[t].v;
  for (int i = 0; i < 3; ++i) {
    const TinVertex& a = tin.vertices[v[(i + 1) % 3]];
    const TinVertex& b = tin.vertices[v[(i + 2) % 3]];
    if (Orientation({a.x, a.y}, {b.x, b.y}, p) < 0) return false;
  }
  return true;
}

// Whether the station is at a corner of triangle t.
bool IsCorner(const Tin& tin, size_t t, const Station& s) {
  for (uint32_t v : tin.triangles[t].v)
    if (tin.vertices[v].x == s.x && tin.vertices[v].y == s.y) return true;
  return false;
}

// Some triangle holding p, by testing them all.
int64_t BruteLocate(const Tin& tin, const Point2& p) {
  for (size_t t = 0; t < tin.triangles.size(); ++t)
    if (Holds(tin, t, p)) return static_cast<int64_t>(t);
  return -1;
}

Result<LineWalk> Walk(const Tin& tin, const std::vector<Point2>& line) {
  return WalkLine(line, BruteLocate(tin, line.front()), ReaderOf(tin));
}

// Every station: z on the plane, distance as measured along the line; every stretch's middle
// lies in its triangle.
void ExpectConsistent(const Tin& tin, const LineWalk& w, double total) {
  ASSERT_EQ(w.triangles.size() + 1, w.stations.size());
  for (const Station& s : w.stations) EXPECT_NEAR(s.z, Plane(s.x, s.y), 1e-9) << s.x << " " << s.y;
  for (size_t i = 0; i + 1 < w.stations.size(); ++i) {
    EXPECT_LE(w.stations[i].distance, w.stations[i + 1].distance);
    const Point2 mid{(w.stations[i].x + w.stations[i + 1].x) / 2,
                     (w.stations[i].y + w.stations[i + 1].y) / 2};
    EXPECT_TRUE(Holds(tin, static_cast<size_t>(w.triangles[i]), mid))
        << "stretch " << i << " is not in triangle " << w.triangles[i];
  }
  EXPECT_NEAR(w.stations.back().distance, total, 1e-9);
}

int Count(const LineWalk& w, StationKind kind) {
  return static_cast<int>(std::count_if(w.stations.begin(), w.stations.end(),
                                        [kind](const Station& s) { return s.kind == kind; }));
}

TEST(LineWalk, AcrossCellsCrossesEveryGridLineAndDiagonal) {
  const Tin tin = MakeGridTin(10, 10, 1, 0, 0, Plane);
  auto w = Walk(tin, {{0.5, 0.25}, {9.5, 0.25}});
  ASSERT_TRUE(w.ok()) << w.status().ToString();
  // Nine vertical grid lines, and the diagonals of the eight inner cells (those of the first
  // and last cell meet y = 0.25 at x = 0.25 and 9.75, beyond the line's ends).
  EXPECT_EQ(Count(*w, StationKind::kEdge), 17);
  EXPECT_EQ(Count(*w, StationKind::kVertex), 0);
  EXPECT_EQ(w->stations.front().kind, StationKind::kStart);
  EXPECT_EQ(w->stations.back().kind, StationKind::kEnd);
  ExpectConsistent(tin, *w, 9);
  for (const Station& s : w->stations) EXPECT_EQ(s.y, 0.25);
}

TEST(LineWalk, AlongAGridLinePassesThroughItsVertices) {
  const Tin tin = MakeGridTin(10, 10, 1, 0, 0, Plane);
  auto w = Walk(tin, {{0.5, 2}, {9.5, 2}});
  ASSERT_TRUE(w.ok()) << w.status().ToString();
  EXPECT_EQ(Count(*w, StationKind::kVertex), 9);
  EXPECT_EQ(Count(*w, StationKind::kEdge), 0);
  ExpectConsistent(tin, *w, 9);
  for (int k = 1; k <= 9; ++k) EXPECT_EQ(w->stations[k].x, k);
}

TEST(LineWalk, FromAVertexAlongDiagonalEdgesToAVertex) {
  const Tin tin = MakeGridTin(10, 10, 1, 0, 0, Plane);
  auto w = Walk(tin, {{0, 0}, {10, 10}});
  ASSERT_TRUE(w.ok()) << w.status().ToString();
  EXPECT_EQ(w->stations.size(), 11u);
  EXPECT_EQ(Count(*w, StationKind::kVertex), 9);
  ExpectConsistent(tin, *w, std::sqrt(200.0));
  // Backwards too, from the far corner (a vertex with one triangle).
  auto back = Walk(tin, {{10, 10}, {0, 0}});
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->stations.size(), 11u);
  ExpectConsistent(tin, *back, std::sqrt(200.0));
}

TEST(LineWalk, BendsAndRepeatedPointsKeepTheDistanceRunning) {
  const Tin tin = MakeGridTin(10, 10, 1, 0, 0, Plane);
  auto w = Walk(tin, {{1.5, 1.5}, {1.5, 1.5}, {4.5, 1.5}, {4.5, 5.5}, {4.5, 5.5}});
  ASSERT_TRUE(w.ok()) << w.status().ToString();
  EXPECT_EQ(Count(*w, StationKind::kBend), 1);
  EXPECT_EQ(Count(*w, StationKind::kEnd), 1);
  ExpectConsistent(tin, *w, 7);
  for (const Station& s : w->stations) {
    if (s.kind == StationKind::kBend) {
      EXPECT_EQ(s.distance, 3);
    }
  }
}

TEST(LineWalk, ALineLeavingTheSurfaceIsRefusedNamingWhere) {
  const Tin tin = MakeGridTin(10, 10, 1, 0, 0, Plane);
  auto out = Walk(tin, {{5, 5}, {15, 5}});
  ASSERT_FALSE(out.ok());
  EXPECT_EQ(out.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(out.status().message().find("leaves the surface at (10, 5) on its way to point 2"),
            std::string::npos)
      << out.status().message();
  // From a boundary point straight out, and out through a corner vertex.
  auto edge = Walk(tin, {{10, 5}, {12, 5}});
  ASSERT_FALSE(edge.ok());
  EXPECT_NE(edge.status().message().find("(10, 5)"), std::string::npos);
  auto corner = Walk(tin, {{5, 5}, {10, 10}, {11, 11}});
  ASSERT_FALSE(corner.ok());
  EXPECT_NE(corner.status().message().find("(10, 10) on its way to point 3"), std::string::npos)
      << corner.status().message();
}

TEST(LineWalk, BrokenLinksAreCorruptionNotAWrongAnswer) {
  Tin tin = MakeGridTin(4, 4, 1, 0, 0, Plane);
  // Every triangle's neighbours point at triangle 0, whatever its corners.
  for (TinTriangle& t : tin.triangles)
    for (int32_t& n : t.n)
      if (n != kNoNeighbour) n = 0;
  auto w = Walk(tin, {{0.5, 0.2}, {3.5, 3.7}});
  ASSERT_FALSE(w.ok());
  EXPECT_EQ(w.status().code(), StatusCode::kCorruption) << w.status().ToString();
}

// Random lines over a free TIN (random diagonals, displaced points): z at every station is the
// brute-force plane's, every stretch lies in its triangle, and the walk reads about one triangle
// per station.
TEST(LineWalk, RandomLinesOnAFreeTinAgreeWithBruteForce) {
  for (uint32_t seed = 1; seed <= 300; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Tin tin = testing::PerturbedGridTin(12, 9, seed, 1.0, 0.3);
    for (TinVertex& v : tin.vertices) v.z = Plane(v.x, v.y);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> ux(600000.2, 600010.8), uy(5100000.2, 5100007.8);
    std::vector<Point2> line;
    for (int k = 0; k < 4; ++k) line.push_back({ux(rng), uy(rng)});
    int reads = 0;
    auto w = WalkLine(line, BruteLocate(tin, line.front()), ReaderOf(tin, &reads));
    ASSERT_TRUE(w.ok()) << w.status().ToString();
    double total = 0;
    for (size_t k = 1; k < line.size(); ++k)
      total += std::hypot(line[k].x - line[k - 1].x, line[k].y - line[k - 1].y);
    for (const Station& s : w->stations)
      EXPECT_NEAR(s.z, Plane(s.x, s.y), 1e-6) << s.x << " " << s.y;
    for (size_t i = 0; i + 1 < w->stations.size(); ++i) {
      const Point2 mid{(w->stations[i].x + w->stations[i + 1].x) / 2,
                       (w->stations[i].y + w->stations[i + 1].y) / 2};
      EXPECT_TRUE(Holds(tin, static_cast<size_t>(w->triangles[i]), mid)) << "stretch " << i;
    }
    EXPECT_NEAR(w->stations.back().distance, total, 1e-6);
    EXPECT_LE(reads, static_cast<int>(w->stations.size()) + 4);
  }
}

// Lines from vertex to vertex of a free TIN, and along its boundary, pass through vertices and
// run along edges: the walk decides every one of those by exact predicates and still agrees
// with brute force.
TEST(LineWalk, VertexToVertexAndAlongTheBoundaryOnAFreeTin) {
  for (uint32_t seed = 1; seed <= 300; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Tin tin = testing::PerturbedGridTin(10, 8, seed, 1.0, 0.3);
    for (TinVertex& v : tin.vertices) v.z = Plane(v.x, v.y);
    std::mt19937 rng(seed);
    std::uniform_int_distribution<size_t> pick(0, tin.vertices.size() - 1);
    std::vector<Point2> line;
    for (int k = 0; k < 5; ++k) {
      const TinVertex& v = tin.vertices[pick(rng)];
      line.push_back({v.x, v.y});
    }
    // Then round the boundary (its vertices are never displaced) counter-clockwise.
    for (const Point2& corner :
         {Point2{600000, 5100000}, Point2{600009, 5100000}, Point2{600009, 5100007},
          Point2{600000, 5100007}, Point2{600000, 5100000}})
      line.push_back(corner);
    auto w = Walk(tin, line);
    ASSERT_TRUE(w.ok()) << w.status().ToString();
    for (const Station& s : w->stations)
      EXPECT_NEAR(s.z, Plane(s.x, s.y), 1e-6) << s.x << " " << s.y;
    for (size_t i = 0; i + 1 < w->stations.size(); ++i) {
      const Point2 mid{(w->stations[i].x + w->stations[i + 1].x) / 2,
                       (w->stations[i].y + w->stations[i + 1].y) / 2};
      // A stretch along an edge joins two corners, and its rounded middle may fall either side.
      const size_t t = static_cast<size_t>(w->triangles[i]);
      EXPECT_TRUE(Holds(tin, t, mid) ||
                  (IsCorner(tin, t, w->stations[i]) && IsCorner(tin, t, w->stations[i + 1])))
          << "stretch " << i;
      EXPECT_LE(w->stations[i].distance, w->stations[i + 1].distance);
    }
    // The boundary's 9 + 7 + 9 + 7 unit edges meet at 28 vertices besides the 4 corners.
    EXPECT_GE(Count(*w, StationKind::kVertex), 28);
  }
}

}  // namespace
}  // namespace tinbase
