// The CGAL adapter: bulk insertion with our indices, constraints by index pair (including the
// CGAL edge cases of docs/design.md, "Pitfalls"), crossing vertices, and extraction into a Tin.
#include "core/geometry/cdt.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <random>
#include <set>

#include "core/geometry/predicates.h"
#include "tests/support/thread_count.h"
#include "tests/support/tin_checks.h"

namespace tinbase {
namespace {

using testing::ExpectConstraintsAreEdges;
using testing::ExpectCounterClockwise;
using testing::ExpectEulerDisc;
using testing::ExpectLocallyDelaunay;
using testing::ExpectNeighboursConsistent;

void ExpectValid(const Tin& tin) {
  ExpectCounterClockwise(tin);
  ExpectNeighboursConsistent(tin);
  ExpectLocallyDelaunay(tin);
  ExpectConstraintsAreEdges(tin);
  ExpectEulerDisc(tin);
}

std::vector<TinVertex> RandomPoints(size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<double> coord(0, 1000);
  std::vector<TinVertex> points(n);
  for (TinVertex& p : points) p = {600000 + coord(rng), 5100000 + coord(rng), coord(rng) / 10};
  return points;
}

bool HasEdge(const Tin& tin, uint32_t a, uint32_t b) {
  for (const TinTriangle& t : tin.triangles) {
    for (int i = 0; i < 3; ++i) {
      if ((t.v[i] == a && t.v[(i + 1) % 3] == b) || (t.v[i] == b && t.v[(i + 1) % 3] == a)) {
        return true;
      }
    }
  }
  return false;
}

std::set<std::pair<uint32_t, uint32_t>> ConstraintSet(const Tin& tin) {
  std::set<std::pair<uint32_t, uint32_t>> set;
  for (auto [a, b] : tin.constraints) set.insert({std::min(a, b), std::max(a, b)});
  return set;
}

// ToTin gathers constraints in its walk over the faces: an edge on the hull, whose other face is
// infinite, counts as much as an inner one, and each comes out once.
TEST(CdtTest, ToTinListsEachConstrainedEdgeOnceHullEdgesIncluded) {
  Cdt cdt;
  cdt.InsertVertices({{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}, {5, 4, 0}});
  const std::vector<std::pair<uint32_t, uint32_t>> edges{{0, 1}, {1, 2}, {2, 3},
                                                         {3, 0}, {0, 4}, {4, 2}};
  for (const auto& [a, b] : edges) cdt.InsertConstraint(a, b);
  const Tin tin = cdt.ToTin();
  ASSERT_EQ(tin.constraints.size(), edges.size());
  std::set<std::pair<uint32_t, uint32_t>> want;
  for (const auto& [a, b] : edges) want.insert({std::min(a, b), std::max(a, b)});
  EXPECT_EQ(ConstraintSet(tin), want);
  // Collinear vertices: no triangle, the constraint still listed.
  Cdt line;
  line.InsertVertices({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});
  line.InsertConstraint(0, 2);
  const Tin on_line = line.ToTin();
  EXPECT_TRUE(on_line.triangles.empty());
  EXPECT_EQ(ConstraintSet(on_line), (std::set<std::pair<uint32_t, uint32_t>>{{0, 1}, {1, 2}}));
}

TEST(CdtTest, BulkInsertionKeepsInputOrderAndData) {
  const unsigned seed = std::random_device{}();
  std::printf("BulkInsertionKeepsInputOrderAndData seed %u\n", seed);
  std::mt19937 rng(seed);
  const std::vector<TinVertex> points = RandomPoints(5000, rng);
  Cdt cdt;
  const std::vector<uint32_t> index = cdt.InsertVertices(points);
  ASSERT_EQ(index.size(), points.size());
  for (uint32_t i = 0; i < index.size(); ++i) EXPECT_EQ(index[i], i);
  const Tin tin = cdt.ToTin();
  ASSERT_EQ(tin.vertices.size(), points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(tin.vertices[i].x, points[i].x);
    EXPECT_EQ(tin.vertices[i].y, points[i].y);
    EXPECT_EQ(tin.vertices[i].z, points[i].z);
    EXPECT_EQ(tin.vertices[i].kind, VertexKind::kDem);
  }
  EXPECT_EQ(tin.triangles.size(), cdt.FaceCount());
  EXPECT_TRUE(tin.constraints.empty());
  ExpectValid(tin);
  for (const TinTriangle& t : tin.triangles) EXPECT_TRUE(t.visible);
}

TEST(CdtTest, DuplicatesMapToTheFirstVertex) {
  std::vector<TinVertex> points = {{0, 0, 1}, {10, 0, 2}, {0, 10, 3}, {10, 0, 99}, {5, 5, 4}};
  Cdt cdt;
  EXPECT_EQ(cdt.InsertVertices(points), (std::vector<uint32_t>{0, 1, 2, 1, 3}));
  // Later single and bulk insertions of existing positions also map to the existing vertex.
  EXPECT_EQ(cdt.InsertVertex({0, 10, 42}), 2u);
  EXPECT_EQ(cdt.InsertVertices({{7, 1, 0}, {5, 5, 0}}), (std::vector<uint32_t>{4, 3}));
  const Tin tin = cdt.ToTin();
  ASSERT_EQ(tin.vertices.size(), 5u);
  EXPECT_EQ(tin.vertices[1].z, 2);
  EXPECT_EQ(tin.vertices[2].z, 3);
  ExpectValid(tin);
}

TEST(CdtTest, IncidentFacesAreTheStarOfTheNewVertex) {
  std::mt19937 rng(7);
  Cdt cdt;
  cdt.InsertVertices(RandomPoints(300, rng));
  std::vector<Cdt::FaceRef> incident;
  const std::vector<Cdt::FaceRef> faces = cdt.FiniteFaces();
  const uint32_t v =
      cdt.InsertVertex({600500.5, 5100500.25, 7}, faces[faces.size() / 2], &incident);
  ASSERT_GE(incident.size(), 3u);
  std::set<std::array<uint32_t, 3>> star;
  for (Cdt::FaceRef f : incident) {
    const auto fv = cdt.FaceVertices(f);
    EXPECT_TRUE(fv[0] == v || fv[1] == v || fv[2] == v);
    star.insert(fv);
  }
  EXPECT_EQ(star.size(), incident.size());
  const Tin tin = cdt.ToTin();
  size_t degree = 0;
  for (const TinTriangle& t : tin.triangles) {
    degree += (t.v[0] == v || t.v[1] == v || t.v[2] == v);
  }
  EXPECT_EQ(degree, incident.size());
  // Stamps belong to faces and survive until changed.
  cdt.SetFaceStamp(incident[0], 12345);
  EXPECT_EQ(cdt.FaceStamp(incident[0]), 12345u);
  ExpectValid(tin);
}

std::set<std::array<uint32_t, 3>> FaceSet(const Tin& tin) {
  std::set<std::array<uint32_t, 3>> faces;
  for (const TinTriangle& t : tin.triangles) {
    std::array<uint32_t, 3> key = t.v;
    std::sort(key.begin(), key.end());
    faces.insert(key);
  }
  return faces;
}

// A side x side grid of points `spacing` m apart: a triangulation of its four corners, and the
// other points in the order `rng` shuffles them into.
std::vector<TinVertex> GridCornersThenShuffled(int side, double spacing, std::mt19937& rng,
                                               Cdt& cdt) {
  const auto at = [&](int c, int r) {
    return TinVertex{500000.0 + spacing * c, 5000000.0 + spacing * r, 0};
  };
  cdt.InsertVertices({at(0, 0), at(side - 1, 0), at(0, side - 1), at(side - 1, side - 1)});
  std::vector<TinVertex> inner;
  for (int r = 0; r < side; ++r)
    for (int c = 0; c < side; ++c)
      if ((c % (side - 1) != 0) || (r % (side - 1) != 0)) inner.push_back(at(c, r));
  std::shuffle(inner.begin(), inner.end(), rng);
  return inner;
}

// On a grid every cell's corners are co-circular, so either diagonal is Delaunay. A new vertex
// keeps the diagonals that were there (as strict in-circle flips do) rather than taking CGAL's
// symbolic perturbation: no edge from it ends up as the diagonal of a co-circular quad. And
// every face the insertion made, including those across a kept diagonal, is reported.
TEST(CdtTest, NewVertexKeepsCoCircularDiagonals) {
  std::mt19937 rng(11);
  Cdt cdt;
  const std::vector<TinVertex> inner = GridCornersThenShuffled(9, 10, rng, cdt);
  int tied_quads_seen = 0;
  for (const TinVertex& p : inner) {
    const auto before = FaceSet(cdt.ToTin());
    std::vector<Cdt::FaceRef> incident;
    const uint32_t v = cdt.InsertVertex(p, {}, &incident);
    std::set<std::array<uint32_t, 3>> reported;
    for (Cdt::FaceRef f : incident) {
      std::array<uint32_t, 3> key = cdt.FaceVertices(f);
      std::sort(key.begin(), key.end());
      reported.insert(key);
    }
    const Tin tin = cdt.ToTin();
    for (const auto& face : FaceSet(tin)) {
      if (before.count(face)) continue;
      EXPECT_TRUE(reported.count(face)) << "an unreported new face";
    }
    for (const TinTriangle& t : tin.triangles) {
      for (int i = 0; i < 3; ++i) {
        // The edge opposite v[i], if it comes from v, with the apex across it.
        const uint32_t a = t.v[(i + 1) % 3], b = t.v[(i + 2) % 3];
        if ((a != v && b != v) || t.n[i] == kNoNeighbour) continue;
        const TinTriangle& u = tin.triangles[t.n[i]];
        uint32_t apex = u.v[0];
        for (uint32_t w : u.v)
          if (w != a && w != b) apex = w;
        const auto& q = tin.vertices;
        const int side = InCircle({q[t.v[0]].x, q[t.v[0]].y}, {q[t.v[1]].x, q[t.v[1]].y},
                                  {q[t.v[2]].x, q[t.v[2]].y}, {q[apex].x, q[apex].y});
        EXPECT_NE(side, 0) << "vertex " << v << " took a co-circular diagonal";
        tied_quads_seen += side == 0;
      }
    }
    ExpectValid(tin);
  }
  EXPECT_EQ(tied_quads_seen, 0);
}

// Without constraints an insertion is strict: a face survives unless the new point lies strictly
// inside its circumcircle. Flipping CGAL's tie-breaks back afterwards (the older way) broke this
// after a chain of ties, leaving other diagonals inside a co-circular polygon.
TEST(CdtTest, NewVertexChangesOnlyFacesWhoseCircleHoldsItStrictly) {
  const unsigned seed = std::random_device{}();
  std::printf("NewVertexChangesOnlyFacesWhoseCircleHoldsItStrictly seed %u\n", seed);
  std::mt19937 rng(seed);
  Cdt cdt;
  const std::vector<TinVertex> inner = GridCornersThenShuffled(11, 1, rng, cdt);
  for (const TinVertex& p : inner) {
    const Tin before = cdt.ToTin();
    cdt.InsertVertex(p);
    const auto after = FaceSet(cdt.ToTin());
    for (const TinTriangle& t : before.triangles) {
      const auto& q = before.vertices;
      const int side = InCircle({q[t.v[0]].x, q[t.v[0]].y}, {q[t.v[1]].x, q[t.v[1]].y},
                                {q[t.v[2]].x, q[t.v[2]].y}, {p.x, p.y});
      std::array<uint32_t, 3> key = t.v;
      std::sort(key.begin(), key.end());
      if (side > 0) continue;
      EXPECT_TRUE(after.count(key)) << "a face the point is not strictly inside went";
    }
  }
}

// FaceCorners reads positions from the triangulation; they are vertices()'s, crossings included
// once indexed.
TEST(CdtTest, FaceCornersAreTheVerticesOfTheFace) {
  Cdt cdt;
  cdt.InsertVertices({{0, 0, 100}, {10, 0, 101}, {10, 10, 102}, {0, 10, 103}, {3, 1, 50}});
  cdt.InsertConstraint(0, 2);
  cdt.InsertConstraint(1, 3);
  cdt.IndexCrossings([](double x, double y) { return 1000 + x + 2 * y; });
  const std::vector<Cdt::FaceRef> faces = cdt.FiniteFaces();
  ASSERT_FALSE(faces.empty());
  for (Cdt::FaceRef f : faces) {
    const std::array<uint32_t, 3> v = cdt.FaceVertices(f);
    const std::array<Cdt::Corner, 3> corners = cdt.FaceCorners(f);
    for (size_t i = 0; i < 3; ++i) {
      EXPECT_EQ(corners[i].index, v[i]);
      const TinVertex& want = cdt.vertices()[v[i]];
      EXPECT_EQ(corners[i].x, want.x);
      EXPECT_EQ(corners[i].y, want.y);
      EXPECT_EQ(corners[i].z, want.z);
    }
  }
}

// Two triangulations of lattice points (co-circular quads everywhere) on either side of the
// column `seam`, both holding the same points on it: joined, they are one Delaunay triangulation
// of every point, and each face not reported changed is a face of an input, the same vertices in
// the same order.
TEST(CdtTest, AbsorbJoinsTwoSidesIntoOneDelaunayTriangulation) {
  const unsigned seed = std::random_device{}();
  std::printf("AbsorbJoinsTwoSidesIntoOneDelaunayTriangulation seed %u\n", seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int round = 0; round < 30; ++round) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " round " + std::to_string(round));
    const int width = 3 + static_cast<int>(rng() % 40), height = 2 + static_cast<int>(rng() % 40);
    const int seam = 1 + static_cast<int>(rng() % (width - 2));
    const double density = unit(rng);
    const auto at = [&](int c, int r) {
      return TinVertex{500000.0 + 10 * c, 5000000.0 + 10 * r, 100 * unit(rng)};
    };
    std::vector<TinVertex> left, right, on_seam;
    for (int r = 0; r < height; ++r) {
      const bool end = r == 0 || r == height - 1;
      if (end || unit(rng) < density) on_seam.push_back(at(seam, r));
      for (int c = 0; c < width; ++c) {
        if (c == seam || !(unit(rng) < density || (end && (c == 0 || c == width - 1)))) continue;
        (c < seam ? left : right).push_back(at(c, r));
      }
    }
    left.insert(left.end(), on_seam.begin(), on_seam.end());
    right.insert(right.end(), on_seam.begin(), on_seam.end());
    Cdt joined, other;
    joined.InsertVertices(left);
    other.InsertVertices(right);
    const Tin left_tin = joined.ToTin(), right_tin = other.ToTin();

    std::vector<Cdt::FaceRef> changed;
    const std::vector<uint32_t> index = joined.Absorb(std::move(other), &changed);
    const Tin tin = joined.ToTin();
    ExpectValid(tin);
    ASSERT_EQ(tin.vertices.size(), left.size() + right.size() - on_seam.size());
    ASSERT_EQ(index.size(), right.size());
    for (size_t k = 0; k < right.size(); ++k) {
      EXPECT_EQ(tin.vertices[index[k]].x, right_tin.vertices[k].x);
      EXPECT_EQ(tin.vertices[index[k]].y, right_tin.vertices[k].y);
    }
    double area = 0;
    for (const TinTriangle& t : tin.triangles) {
      const TinVertex &a = tin.vertices[t.v[0]], &b = tin.vertices[t.v[1]],
                      &c = tin.vertices[t.v[2]];
      area += 0.5 * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
    }
    EXPECT_NEAR(area, 100.0 * (width - 1) * (height - 1), 1e-6);

    // Faces as written, rotated to start at their lowest index (orientation kept).
    const auto canonical = [](std::array<uint32_t, 3> v) {
      std::rotate(v.begin(), std::min_element(v.begin(), v.end()), v.end());
      return v;
    };
    std::set<std::array<uint32_t, 3>> inputs, reported;
    for (const TinTriangle& t : left_tin.triangles) inputs.insert(canonical(t.v));
    for (const TinTriangle& t : right_tin.triangles)
      inputs.insert(canonical({index[t.v[0]], index[t.v[1]], index[t.v[2]]}));
    for (Cdt::FaceRef f : changed) reported.insert(canonical(joined.FaceVertices(f)));
    const double seam_x = 500000.0 + 10 * seam;
    for (const TinTriangle& t : tin.triangles) {
      const auto face = canonical(t.v);
      if (reported.count(face)) continue;
      EXPECT_TRUE(inputs.count(face)) << "a changed face was not reported";
      for (uint32_t v : t.v)
        EXPECT_NE(tin.vertices[v].x, seam_x) << "a face on the seam was not reported";
    }
  }
}

TEST(CdtTest, CollinearInputHasNoTriangles) {
  Cdt cdt;
  cdt.InsertVertices({{0, 0, 0}, {1, 1, 0}, {2, 2, 0}, {3, 3, 0}});
  std::vector<Cdt::FaceRef> incident;
  cdt.InsertVertex({4, 4, 0}, {}, &incident);
  EXPECT_TRUE(incident.empty());
  const Tin tin = cdt.ToTin();
  EXPECT_EQ(tin.vertices.size(), 5u);
  EXPECT_TRUE(tin.triangles.empty());
}

TEST(CdtTest, CrossingConstraintsGetASteinerVertexWithCallerElevation) {
  // A square and its two diagonals: they cross at (5, 5).
  Cdt cdt;
  cdt.InsertVertices({{0, 0, 100}, {10, 0, 100}, {10, 10, 100}, {0, 10, 100}, {3, 1, 50}});
  cdt.InsertConstraint(0, 2);
  cdt.InsertConstraint(1, 3);
  int calls = 0;
  const Tin tin = cdt.ToTin([&](double x, double y) {
    ++calls;
    return 1000 + x + 2 * y;  // not on any plane through the vertices: CGAL's z would differ
  });
  ASSERT_EQ(tin.vertices.size(), 6u);
  const TinVertex& s = tin.vertices[5];
  EXPECT_EQ(s.kind, VertexKind::kSteiner);
  EXPECT_NEAR(s.x, 5, 1e-12);
  EXPECT_NEAR(s.y, 5, 1e-12);
  EXPECT_EQ(s.z, 1000 + s.x + 2 * s.y);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(ConstraintSet(tin),
            (std::set<std::pair<uint32_t, uint32_t>>{{0, 5}, {2, 5}, {1, 5}, {3, 5}}));
  ExpectValid(tin);
  // Extraction is repeatable: the crossing keeps its index.
  const Tin again = cdt.ToTin([](double, double) { return -1.0; });
  EXPECT_EQ(again.vertices.size(), 6u);
  EXPECT_EQ(again.vertices[5].z, s.z);
}

// CGAL/cgal#3267: the same constraint twice (and reversed) with projection traits.
TEST(CdtTest, Issue3267DuplicateConstraintListedOnce) {
  Cdt cdt;
  cdt.InsertVertices({{0, 0, 1}, {10, 0, 2}, {10, 10, 3}, {0, 10, 4}, {5, 2, 5}});
  cdt.InsertConstraint(0, 2);
  cdt.InsertConstraint(0, 2);
  cdt.InsertConstraint(2, 0);
  const Tin tin = cdt.ToTin([](double, double) { return 0.0; });
  EXPECT_EQ(tin.vertices.size(), 5u);
  EXPECT_EQ(ConstraintSet(tin), (std::set<std::pair<uint32_t, uint32_t>>{{0, 2}}));
  ExpectValid(tin);
}

// CGAL/cgal#2999: constraints that touch (one ends on the inside of another) and a constraint
// through an existing vertex (Tinfour #118: a point on a constrained edge keeps both halves).
TEST(CdtTest, Issue2999TouchingConstraintsAndVertexOnConstraint) {
  Cdt cdt;
  cdt.InsertVertices({{0, 0, 0},
                      {20, 0, 0},
                      {20, 20, 0},
                      {0, 20, 0},
                      {10, 10, 0},        // 4: on the diagonal 0-2
                      {10, 3, 0},         // 5
                      {15.0, 15.0, 0}});  // 6: on the diagonal too
  cdt.InsertConstraint(0, 2);
  cdt.InsertConstraint(5, 4);  // touches the diagonal at an existing vertex
  cdt.InsertConstraint(1, 3);  // crosses the diagonal at vertex 4 exactly: no Steiner point
  int calls = 0;
  const Tin tin = cdt.ToTin([&](double, double) { return ++calls, 0.0; });
  EXPECT_EQ(calls, 0);
  EXPECT_EQ(tin.vertices.size(), 7u);
  EXPECT_EQ(ConstraintSet(tin), (std::set<std::pair<uint32_t, uint32_t>>{
                                    {0, 4}, {4, 6}, {2, 6}, {4, 5}, {1, 4}, {3, 4}}));
  // A vertex inserted later onto a constrained edge splits it and keeps it constrained.
  const uint32_t on_edge = cdt.InsertVertex({5, 5, 0});
  const Tin after = cdt.ToTin([](double, double) { return 0.0; });
  const auto constraints = ConstraintSet(after);
  EXPECT_TRUE(constraints.count({0, on_edge}));
  EXPECT_TRUE(constraints.count({4, on_edge}));
  EXPECT_FALSE(constraints.count({0, 4}));
  EXPECT_TRUE(HasEdge(after, 0, on_edge));
  ExpectValid(after);
}

// CGAL/cgal#6602: the crossing of x = 0 with y = -15 is constructed at x = -1.78e-15; CGAL
// then walks on from there, passes beside the vertex (0, 0) that lies exactly on the
// constraint and leaves it unconstrained. Found by the constrained rebuild property test.
TEST(CdtTest, Issue6602InexactCrossingDoesNotSkipVertexOnConstraint) {
  Cdt cdt;
  cdt.InsertVertices({{-20, -20, 0},
                      {-15, -15, 0},
                      {20.253100100000001, -15, 0},
                      {0, -20, 0},
                      {0, 0, 0},
                      {0, 10, 0},
                      {40, 40, 0},
                      {-40, 40, 0},
                      {10, 0, 0},
                      {-10, 0, 0}});
  cdt.InsertConstraint(1, 2);
  cdt.InsertConstraint(3, 5);
  const Tin tin = cdt.ToTin([](double x, double y) { return x + y; });
  ASSERT_EQ(tin.vertices.size(), 11u);
  EXPECT_EQ(tin.vertices[10].kind, VertexKind::kSteiner);
  EXPECT_NEAR(tin.vertices[10].x, 0, 1e-12);
  EXPECT_EQ(tin.vertices[10].y, -15);
  EXPECT_EQ(ConstraintSet(tin),
            (std::set<std::pair<uint32_t, uint32_t>>{{1, 10}, {2, 10}, {3, 10}, {4, 10}, {4, 5}}));
  ExpectValid(tin);
}

TEST(CdtTest, ManyCrossingConstraintsStayValid) {
  const unsigned seed = std::random_device{}();
  std::printf("ManyCrossingConstraintsStayValid seed %u\n", seed);
  std::mt19937 rng(seed);
  Cdt cdt;
  const auto points = RandomPoints(400, rng);
  cdt.InsertVertices(points);
  std::uniform_int_distribution<uint32_t> pick(0, 399);
  for (int i = 0; i < 40; ++i) {
    const uint32_t a = pick(rng), b = pick(rng);
    if (a != b) cdt.InsertConstraint(a, b);
  }
  const Tin tin = cdt.ToTin([](double x, double y) { return x - y; });
  ExpectValid(tin);
  for (size_t i = points.size(); i < tin.vertices.size(); ++i) {
    EXPECT_EQ(tin.vertices[i].kind, VertexKind::kSteiner);
    EXPECT_EQ(tin.vertices[i].z, tin.vertices[i].x - tin.vertices[i].y);
  }
}

// A triangulation of several of ToTin's chunks of faces converts to the same Tin, constraints
// in the same order, on 1, 2 and 4 threads.
TEST(CdtTest, ToTinIsTheSameOnAnyNumberOfThreads) {
  const unsigned seed = std::random_device{}();
  std::printf("ToTinIsTheSameOnAnyNumberOfThreads seed %u\n", seed);
  std::mt19937 rng(seed);
  constexpr uint32_t kPoints = 60000;  // about 120000 faces: four chunks
  Cdt cdt;
  cdt.InsertVertices(RandomPoints(kPoints, rng));
  std::uniform_int_distribution<uint32_t> pick(0, kPoints - 1);
  for (int i = 0; i < 60; ++i) {
    const uint32_t a = pick(rng), b = pick(rng);
    if (a != b) cdt.InsertConstraint(a, b);
  }
  const ElevationFn elevation = [](double x, double y) { return x - y; };
  const Tin one = testing::WithThreads(1, [&] { return cdt.ToTin(elevation); });
  ASSERT_FALSE(one.constraints.empty());
  ASSERT_GT(one.triangles.size(), 100000u);
  for (int threads : testing::kThreadCounts) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    testing::ExpectSameTin(testing::WithThreads(threads, [&] { return cdt.ToTin(elevation); }),
                           one);
  }
}

// Triangles sorted the way a store writes them: by a 30 m cell of the centroid, row by row.
int64_t CentroidCell(const std::vector<TinVertex>& points, const TinTriangle& t) {
  double x = 0, y = 0;
  for (uint32_t v : t.v) {
    x += points[v].x;
    y += points[v].y;
  }
  return static_cast<int64_t>(std::floor(y / 30)) * 1000000 +
         static_cast<int64_t>(std::floor(x / 30));
}

// Assembles the batches of InsertVerticesInBands into a Tin, checking the hand-over contract on
// the way: batches continue the numbering, are sorted by their keys, and each link fills a
// neighbour that was left open. Counts the batches before the last that held triangles.
Tin AssembleBands(const std::vector<TinVertex>& points, int bands, int* early_batches,
                  size_t* links) {
  Tin tin;
  tin.vertices = points;
  Cdt cdt;
  const auto order = [&](const TinTriangle& t) { return CentroidCell(points, t); };
  int batches = 0;
  *early_batches = 0;
  *links = 0;
  cdt.InsertVerticesInBands(points, bands, order, [&](TriangleBatch batch) {
    ++batches;
    EXPECT_EQ(batch.first, tin.triangles.size());
    EXPECT_EQ(batch.keys.size(), batch.triangles.size());
    EXPECT_TRUE(std::is_sorted(batch.keys.begin(), batch.keys.end()));
    for (size_t k = 0; k < batch.triangles.size(); ++k)
      EXPECT_EQ(batch.keys[k], order(batch.triangles[k]));
    for (const TriangleBatch::Link& link : batch.links) {
      ASSERT_LT(link.triangle, batch.first);
      EXPECT_EQ(tin.triangles[link.triangle].n[link.slot], kNoNeighbour);
      tin.triangles[link.triangle].n[link.slot] = link.neighbour;
    }
    *links += batch.links.size();
    if (batches < bands && !batch.triangles.empty()) ++*early_batches;
    tin.triangles.insert(tin.triangles.end(), batch.triangles.begin(), batch.triangles.end());
  });
  EXPECT_EQ(batches, bands);
  EXPECT_EQ(cdt.vertices().size(), points.size());
  return tin;
}

// Each triangle as its vertex triple starting at the smallest index.
std::set<std::array<uint32_t, 3>> TriangleSet(const Tin& tin) {
  std::set<std::array<uint32_t, 3>> set;
  for (const TinTriangle& t : tin.triangles) {
    const int first = static_cast<int>(std::min_element(t.v.begin(), t.v.end()) - t.v.begin());
    set.insert({t.v[first], t.v[(first + 1) % 3], t.v[(first + 2) % 3]});
  }
  return set;
}

TEST(CdtTest, BandsHandOverTheBulkTriangulationAsItBecomesFinal) {
  const unsigned seed = std::random_device{}();
  std::printf("BandsHandOverTheBulkTriangulationAsItBecomesFinal seed %u\n", seed);
  std::mt19937 rng(seed);
  const std::vector<TinVertex> points = RandomPoints(5000, rng);
  int early = 0;
  size_t links = 0;
  const Tin banded = AssembleBands(points, 5, &early, &links);
  ExpectValid(banded);
  // Points in general position have one Delaunay triangulation: the bulk one.
  Cdt bulk;
  bulk.InsertVertices(points);
  EXPECT_EQ(TriangleSet(banded), TriangleSet(bulk.ToTin()));
  EXPECT_EQ(early, 4) << "every band but the last hands triangles over";
  EXPECT_GT(links, 0u) << "triangles on a band's upper edge get their neighbours later";
}

TEST(CdtTest, BandsOfCoCircularGridPointsStayDelaunay) {
  // Rows of equal y straddle the band limits, and every cell is four co-circular points.
  std::vector<TinVertex> points;
  for (int row = 0; row < 40; ++row)
    for (int col = 0; col < 40; ++col) points.push_back({10.0 * col, 10.0 * row, 0.5 * col});
  int early = 0;
  size_t links = 0;
  const Tin banded = AssembleBands(points, 3, &early, &links);
  ExpectValid(banded);
  EXPECT_EQ(banded.triangles.size(), 2u * 39 * 39);
  EXPECT_EQ(early, 2);
}

TEST(CdtTest, OneBandIsOneBatchOfEverything) {
  std::mt19937 rng(5);
  const std::vector<TinVertex> points = RandomPoints(300, rng);
  int early = 0;
  size_t links = 0;
  const Tin banded = AssembleBands(points, 1, &early, &links);
  ExpectValid(banded);
  EXPECT_EQ(links, 0u);
  Cdt bulk;
  bulk.InsertVertices(points);
  EXPECT_EQ(TriangleSet(banded), TriangleSet(bulk.ToTin()));
}

TEST(CdtTest, BulkInsertionScales) {
  // A million points one by one without hints would take minutes (docs/design.md,
  // "Pitfalls"); sorted bulk insertion of 300k must take a few seconds at most.
  std::mt19937 rng(11);
  const auto points = RandomPoints(300000, rng);
  const auto start = std::chrono::steady_clock::now();
  Cdt cdt;
  cdt.InsertVertices(points);
  const Tin tin = cdt.ToTin();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("300000 points: %zu triangles in %.2f s\n", tin.triangles.size(), seconds);
  EXPECT_LT(seconds, 10);
  ExpectCounterClockwise(tin);
  ExpectEulerDisc(tin);
}

}  // namespace
}  // namespace tinbase
