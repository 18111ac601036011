// Independent checks of a Tin for tests: orientation, neighbours, local Delaunay by CGAL's exact
// predicates, and |TIN - DEM| by brute-force barycentric evaluation. Written without the code
// under test (core/geometry/cdt, the builders) so a shared bug cannot hide. Header-only.
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "core/raster/grid.h"
#include "core/tin/tin.h"

namespace tinbase::testing {

using CheckKernel = CGAL::Exact_predicates_inexact_constructions_kernel;

inline CheckKernel::Point_2 PlanPoint(const Tin& tin, uint32_t v) {
  return {tin.vertices[v].x, tin.vertices[v].y};
}

// Every triangle strictly counter-clockwise (exact orientation), over existing vertices.
inline void ExpectCounterClockwise(const Tin& tin) {
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const auto& v = tin.triangles[t].v;
    for (uint32_t i : v) ASSERT_LT(i, tin.vertices.size()) << "triangle " << t;
    EXPECT_EQ(CGAL::orientation(PlanPoint(tin, v[0]), PlanPoint(tin, v[1]), PlanPoint(tin, v[2])),
              CGAL::LEFT_TURN)
        << "triangle " << t;
  }
}

// The stored neighbours equal what LinkNeighbours derives from the vertex indices.
inline void ExpectNeighboursConsistent(const Tin& tin) {
  Tin relinked = tin;
  ASSERT_TRUE(LinkNeighbours(relinked));
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    EXPECT_EQ(tin.triangles[t].n, relinked.triangles[t].n) << "triangle " << t;
  }
}

// Every interior edge that is not in tin.constraints is locally Delaunay: the far vertex of the
// neighbour is not strictly inside the circumcircle (co-circular ties are allowed).
inline void ExpectLocallyDelaunay(const Tin& tin) {
  std::set<std::pair<uint32_t, uint32_t>> constrained;
  for (auto [a, b] : tin.constraints) constrained.insert({std::min(a, b), std::max(a, b)});
  int64_t violations = 0;
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    for (int i = 0; i < 3; ++i) {
      const int32_t n = tri.n[i];
      if (n == kNoNeighbour) continue;
      const uint32_t a = tri.v[(i + 1) % 3], b = tri.v[(i + 2) % 3];
      if (constrained.count({std::min(a, b), std::max(a, b)})) continue;
      const TinTriangle& other = tin.triangles[static_cast<size_t>(n)];
      uint32_t far = other.v[0];
      for (uint32_t w : other.v) {
        if (w != a && w != b) far = w;
      }
      if (CGAL::side_of_oriented_circle(PlanPoint(tin, tri.v[0]), PlanPoint(tin, tri.v[1]),
                                        PlanPoint(tin, tri.v[2]),
                                        PlanPoint(tin, far)) == CGAL::ON_POSITIVE_SIDE) {
        if (++violations <= 5)
          ADD_FAILURE() << "edge " << a << "-" << b << " of triangle " << t
                        << " is not locally Delaunay";
      }
    }
  }
  EXPECT_EQ(violations, 0);
}

// Every pair in tin.constraints is an edge of some triangle, and is listed once.
inline void ExpectConstraintsAreEdges(const Tin& tin) {
  std::set<std::pair<uint32_t, uint32_t>> edges;
  for (const TinTriangle& t : tin.triangles) {
    for (int i = 0; i < 3; ++i) {
      const uint32_t a = t.v[i], b = t.v[(i + 1) % 3];
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  }
  std::set<std::pair<uint32_t, uint32_t>> listed;
  for (auto [a, b] : tin.constraints) {
    const std::pair<uint32_t, uint32_t> key{std::min(a, b), std::max(a, b)};
    EXPECT_TRUE(edges.count(key)) << "constraint " << a << "-" << b << " is not an edge";
    EXPECT_TRUE(listed.insert(key).second) << "constraint " << a << "-" << b << " listed twice";
  }
}

// Euler's formula for a triangulated disc (the convex hull): V - E + F = 1, with every vertex
// used by some triangle.
inline void ExpectEulerDisc(const Tin& tin) {
  std::vector<bool> used(tin.vertices.size(), false);
  int64_t boundary = 0;
  for (const TinTriangle& t : tin.triangles) {
    for (int i = 0; i < 3; ++i) {
      used[t.v[i]] = true;
      boundary += t.n[i] == kNoNeighbour;
    }
  }
  for (size_t v = 0; v < used.size(); ++v) EXPECT_TRUE(used[v]) << "vertex " << v << " unused";
  const int64_t faces = static_cast<int64_t>(tin.triangles.size());
  const int64_t edges = (3 * faces + boundary) / 2;
  EXPECT_EQ(static_cast<int64_t>(tin.vertices.size()) - edges + faces, 1);
}

struct DemFit {
  double max_error = 0;
  int64_t valid_cells = 0;
  int64_t uncovered_cells = 0;  // valid cells no triangle covers
};

// Evaluates the TIN at every valid cell centre by barycentric interpolation over every
// triangle whose bounding box holds it (in world coordinates), keeping the worst error.
inline DemFit FitToDem(const Tin& tin, const Grid& dem) {
  const GridGeometry& g = dem.geometry;
  std::vector<double> error(dem.cells.size(), -1);
  for (const TinTriangle& t : tin.triangles) {
    const TinVertex& p0 = tin.vertices[t.v[0]];
    const TinVertex& p1 = tin.vertices[t.v[1]];
    const TinVertex& p2 = tin.vertices[t.v[2]];
    const double det = (p1.x - p0.x) * (p2.y - p0.y) - (p2.x - p0.x) * (p1.y - p0.y);
    if (det == 0) continue;
    const double cmin = std::floor(g.ColumnAt(std::min({p0.x, p1.x, p2.x}))) - 1;
    const double cmax = std::ceil(g.ColumnAt(std::max({p0.x, p1.x, p2.x}))) + 1;
    const double ra = g.RowAt(p0.y), rb = g.RowAt(p1.y), rc = g.RowAt(p2.y);
    const int64_t r0 =
        std::max<int64_t>(0, static_cast<int64_t>(std::floor(std::min({ra, rb, rc}))) - 1);
    const int64_t r1 = std::min<int64_t>(
        g.height - 1, static_cast<int64_t>(std::ceil(std::max({ra, rb, rc}))) + 1);
    const int64_t c0 = std::max<int64_t>(0, static_cast<int64_t>(cmin));
    const int64_t c1 = std::min<int64_t>(g.width - 1, static_cast<int64_t>(cmax));
    for (int64_t r = r0; r <= r1; ++r) {
      const double y = g.CellCenterY(r);
      for (int64_t c = c0; c <= c1; ++c) {
        const float value = dem.At(c, r);
        if (std::isnan(value)) continue;
        const double x = g.CellCenterX(c);
        const double l1 = ((x - p0.x) * (p2.y - p0.y) - (p2.x - p0.x) * (y - p0.y)) / det;
        const double l2 = ((p1.x - p0.x) * (y - p0.y) - (x - p0.x) * (p1.y - p0.y)) / det;
        const double l0 = 1 - l1 - l2;
        constexpr double kEps = 1e-9;
        if (l0 < -kEps || l1 < -kEps || l2 < -kEps) continue;
        const double z = l0 * p0.z + l1 * p1.z + l2 * p2.z;
        double& e = error[static_cast<size_t>(r * g.width + c)];
        e = std::max(e, std::fabs(z - value));
      }
    }
  }
  DemFit fit;
  for (size_t i = 0; i < dem.cells.size(); ++i) {
    if (std::isnan(dem.cells[i])) continue;
    ++fit.valid_cells;
    if (error[i] < 0) {
      ++fit.uncovered_cells;
    } else {
      fit.max_error = std::max(fit.max_error, error[i]);
    }
  }
  return fit;
}

}  // namespace tinbase::testing
