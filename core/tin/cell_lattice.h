// Cell lattice: the geometry shared by TIN builders whose vertices are DEM cell centres.
//
// Builders that pick vertices among the cells of a grid (VIP, RTIN) work in "cell space": the
// centre of cell (col, row) is the integer point (col, row). World coordinates are an
// axis-aligned affine image of it, so planes, containment and barycentric values agree in both,
// and cell space makes rasterisation exact. This header holds what those builders share: the
// rasterisation of a lattice triangle, the plane through it, the elevation a vertex takes on a
// nodata cell, the visibility rule for nodata and the measurement of |TIN - DEM| over the valid
// cells. (core/tin/greedy_builder.cc predates it and keeps private copies of the same rules.)
//
// Thread-safety: free functions are pure; a NodataElevation is not synchronised (it caches).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/base/status.h"
#include "core/raster/grid.h"
#include "core/tin/tin.h"

namespace tinbase {

struct Cell {
  int32_t col = 0;
  int32_t row = 0;
};

// z = z0 + a (col - c0) + b (row - r0) through a lattice triangle's three vertices.
struct CellPlane {
  double a = 0;
  double b = 0;
  double z0 = 0;
  int32_t c0 = 0;
  int32_t r0 = 0;
  double At(double col, double row) const { return z0 + a * (col - c0) + b * (row - r0); }
};

// Ok when a builder can work on `dem`: InvalidArgument, its message starting with `builder`
// ("VIP TIN"), for an empty grid, one narrower than 2 x 2 cells (its corners span no triangle),
// cells that do not match the geometry, or no valid cell at all.
Status ValidateLatticeGrid(const Grid& dem, const std::string& builder);

// Returns false for a triangle of zero area (it covers no cell centre of its own), else sets
// `plane` through the three (cell, z) points.
bool PlaneThrough(const std::array<Cell, 3>& p, const std::array<double, 3>& z, CellPlane* plane);

// Calls span(row, first_col, last_col) for every row of cell centres inside or on the triangle,
// clipped to a width x height grid. Edge crossings are exact rationals of small integers, so the
// tiny margin only absorbs the division's rounding.
template <typename SpanFn>
void RasteriseTriangle(const std::array<Cell, 3>& p, int64_t width, int64_t height, SpanFn&& span) {
  const int32_t row_min = std::max<int32_t>(0, std::min({p[0].row, p[1].row, p[2].row}));
  const int32_t row_max =
      std::min<int32_t>(static_cast<int32_t>(height - 1), std::max({p[0].row, p[1].row, p[2].row}));
  for (int32_t r = row_min; r <= row_max; ++r) {
    double left = std::numeric_limits<double>::infinity();
    double right = -left;
    for (int e = 0; e < 3; ++e) {
      const Cell& a = p[e];
      const Cell& b = p[(e + 1) % 3];
      if (r < std::min(a.row, b.row) || r > std::max(a.row, b.row)) continue;
      if (a.row == b.row) {
        left = std::min({left, double(a.col), double(b.col)});
        right = std::max({right, double(a.col), double(b.col)});
        continue;
      }
      const double x = a.col + double(r - a.row) * double(b.col - a.col) / double(b.row - a.row);
      left = std::min(left, x);
      right = std::max(right, x);
    }
    const int64_t first = std::max<int64_t>(0, static_cast<int64_t>(std::ceil(left - 1e-9)));
    const int64_t last =
        std::min<int64_t>(width - 1, static_cast<int64_t>(std::floor(right + 1e-9)));
    if (first <= last) span(r, first, last);
  }
}

// The elevation a TIN vertex takes at a cell: the cell's value, or on a nodata cell the mean of
// the valid cells in the smallest square window around it that holds any (the rule of
// greedy_builder.h). A summed-area table of valid-cell counts (built at the first nodata query)
// finds that window's radius by bisection, so a cell deep inside a large void costs
// O(log r + r^2) once, then is cached; a grid without nodata costs nothing extra.
class NodataElevation {
 public:
  // REQUIRES: `dem` has a valid cell and outlives this object.
  explicit NodataElevation(const Grid& dem) : dem_(dem) {}
  double At(int64_t col, int64_t row);

 private:
  void BuildValidPrefix();
  int64_t ValidInWindow(int64_t col, int64_t row, int64_t radius) const;

  const Grid& dem_;
  std::vector<int64_t> valid_prefix_;          // (width + 1) x (height + 1), empty until needed
  std::unordered_map<int64_t, double> cache_;  // by row * width + col, nodata cells only
};

// The cell whose centre a vertex lies on (rounded; exact for vertices placed at cell centres).
Cell CellOf(const GridGeometry& g, const TinVertex& v);

// The cell nearest the centroid of a lattice triangle: (s + 1) / 3 is round(s / 3) for a sum
// s >= 0 of coordinates, and thirds are never a rounding tie. The cell whose data decides whether
// the triangle is part of the surface.
inline Cell CentroidCell(Cell a, Cell b, Cell c) {
  return {(a.col + b.col + c.col + 1) / 3, (a.row + b.row + c.row + 1) / 3};
}

// Sets each triangle's visibility: a triangle whose centroid lies on a nodata cell is not part
// of the surface. REQUIRES: every vertex lies on a cell centre of `dem`.
void HideNodataTriangles(const Grid& dem, Tin& tin);

struct CellFit {
  double max_error = 0;  // largest |TIN - DEM| over the valid cells the triangles cover
  double rms_error = 0;
  int64_t cells = 0;  // valid cells covered, each counted once
};

// Evaluates every triangle's plane at every valid cell it covers (a cell on a shared edge is
// counted once, by the first triangle that covers it). REQUIRES: every vertex lies on a cell
// centre of `dem`.
CellFit MeasureCellFit(const Grid& dem, const Tin& tin);

}  // namespace tinbase
