// Independent checks for TINs whose vertices are DEM cell centres (VIP, RTIN): the triangles
// tile exactly the grid's rectangle of cell centres, with no T-junction, vertices carry their
// cells' values, and visibility follows nodata. Written without the code under test
// (core/tin/cell_lattice, the builders). Header-only.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_set>

#include "core/raster/grid.h"
#include "core/tin/tin.h"

namespace tinbase::testing {

struct LatticePoint {
  int64_t col = 0;
  int64_t row = 0;
};

inline LatticePoint LatticeOf(const GridGeometry& g, const TinVertex& v) {
  return {std::llround(g.ColumnAt(v.x)), std::llround(g.RowAt(v.y))};
}

// Every vertex is exactly a cell centre of `dem`, of kind kDem, with the cell's value when the
// cell holds data.
inline void ExpectVerticesOnCells(const Tin& tin, const Grid& dem) {
  const GridGeometry& g = dem.geometry;
  for (size_t i = 0; i < tin.vertices.size(); ++i) {
    const TinVertex& v = tin.vertices[i];
    EXPECT_EQ(v.kind, VertexKind::kDem);
    const LatticePoint p = LatticeOf(g, v);
    ASSERT_TRUE(p.col >= 0 && p.col < g.width && p.row >= 0 && p.row < g.height) << "vertex " << i;
    EXPECT_EQ(v.x, g.CellCenterX(p.col)) << "vertex " << i;
    EXPECT_EQ(v.y, g.CellCenterY(p.row)) << "vertex " << i;
    if (dem.IsValid(p.col, p.row)) {
      EXPECT_EQ(v.z, dem.At(p.col, p.row)) << "vertex " << i;
    }
  }
}

// The triangles tile the rectangle of cell centres: their areas sum to it, the edges without a
// neighbour all lie on its outline and their lengths sum to its perimeter (an edge left
// unmatched inside, as a T-junction leaves it, would add to that length), and no vertex lies
// inside any triangle's edge.
inline void ExpectTilesGridWithoutTJunctions(const Tin& tin, const Grid& dem) {
  const GridGeometry& g = dem.geometry;
  const double w = std::fabs(g.cell_x) * static_cast<double>(g.width - 1);
  const double h = std::fabs(g.cell_y) * static_cast<double>(g.height - 1);
  double area = 0, boundary = 0;
  std::unordered_set<int64_t> vertex_cells;
  for (const TinVertex& v : tin.vertices) {
    const LatticePoint p = LatticeOf(g, v);
    vertex_cells.insert(p.row * g.width + p.col);
  }
  int64_t t_junctions = 0;
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    const TinVertex& a = tin.vertices[tri.v[0]];
    const TinVertex& b = tin.vertices[tri.v[1]];
    const TinVertex& c = tin.vertices[tri.v[2]];
    area += 0.5 * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
    for (int i = 0; i < 3; ++i) {
      const TinVertex& p = tin.vertices[tri.v[(i + 1) % 3]];
      const TinVertex& q = tin.vertices[tri.v[(i + 2) % 3]];
      const LatticePoint lp = LatticeOf(g, p), lq = LatticeOf(g, q);
      // Lattice points strictly inside the edge, stepping by the reduced direction.
      const int64_t dc = lq.col - lp.col, dr = lq.row - lp.row;
      const int64_t steps = std::gcd(std::llabs(dc), std::llabs(dr));
      for (int64_t s = 1; s < steps; ++s) {
        const int64_t col = lp.col + dc / steps * s, row = lp.row + dr / steps * s;
        if (vertex_cells.count(row * g.width + col) && ++t_junctions <= 5) {
          ADD_FAILURE() << "triangle " << t << ": vertex at cell (" << col << ", " << row
                        << ") lies inside its edge";
        }
      }
      if (tri.n[i] != kNoNeighbour) continue;
      boundary += std::hypot(q.x - p.x, q.y - p.y);
      const bool on_outline = (lp.col == lq.col && (lp.col == 0 || lp.col == g.width - 1)) ||
                              (lp.row == lq.row && (lp.row == 0 || lp.row == g.height - 1));
      EXPECT_TRUE(on_outline) << "triangle " << t << ": unmatched edge (" << lp.col << ", "
                              << lp.row << ")-(" << lq.col << ", " << lq.row
                              << ") is not on the grid's outline";
    }
  }
  EXPECT_EQ(t_junctions, 0);
  EXPECT_NEAR(area, w * h, 1e-9 * w * h);
  EXPECT_NEAR(boundary, 2 * (w + h), 1e-9 * (w + h));
}

// A triangle is visible exactly when its centroid's cell holds data.
inline void ExpectNodataHidden(const Tin& tin, const Grid& dem) {
  const GridGeometry& g = dem.geometry;
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    double x = 0, y = 0;
    for (uint32_t v : tin.triangles[t].v) x += tin.vertices[v].x / 3, y += tin.vertices[v].y / 3;
    const int64_t c = std::llround(g.ColumnAt(x));
    const int64_t r = std::llround(g.RowAt(y));
    EXPECT_EQ(tin.triangles[t].visible, dem.IsValid(c, r)) << "triangle " << t;
  }
}

inline int HiddenTriangles(const Tin& tin) {
  int hidden = 0;
  for (const TinTriangle& t : tin.triangles) hidden += !t.visible;
  return hidden;
}

}  // namespace tinbase::testing
