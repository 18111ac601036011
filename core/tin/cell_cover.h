// CellCover: how a TIN's triangles meet a grid DEM's cells, defined once for the builders, the
// tolerance refiner and the integrity checker (docs/design.md, "Invariants", 6 and 7).
//
//   - A triangle covers the cells whose centres lie inside it or on its edges, decided exactly
//     in world coordinates (HoldsCellCentre), so every cell under the surface is covered by at
//     least one triangle; cells on a shared edge are covered by both. ForEachCellSpan finds the
//     candidates in the grid's "centre space" (core/raster/grid_geometry.h) with a margin for
//     round-off; a candidate is judged only once it would matter (a new worst error), since
//     most cells are far inside.
//   - The triangle's z at a cell centre is its plane through the three vertices' z.
//   - A triangle lies on data when the cell containing its centroid is valid; a triangle whose
//     centroid is on nodata (or off the grid) is not part of the visible surface.
// Thread-safety: pure functions.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "core/geometry/predicates.h"
#include "core/raster/cell_source.h"
#include "core/raster/grid.h"
#include "core/tin/tin.h"

namespace tinbase {

// z = z0 + a (col - c0) + b (row - r0) in centre space.
struct CellPlane {
  double a = 0, b = 0, z0 = 0, c0 = 0, r0 = 0;
  double At(double col, double row) const { return z0 + a * (col - c0) + b * (row - r0); }
};

// A triangle in the centre space of one grid.
struct CellTriangle {
  std::array<double, 3> col{}, row{}, z{};
};

inline CellTriangle ToCellSpace(const GridGeometry& g, const TinVertex& a, const TinVertex& b,
                                const TinVertex& c) {
  CellTriangle t;
  const TinVertex* v[3] = {&a, &b, &c};
  for (int i = 0; i < 3; ++i) {
    t.col[i] = g.ColumnAt(v[i]->x);
    t.row[i] = g.RowAt(v[i]->y);
    t.z[i] = v[i]->z;
  }
  return t;
}

// False for a triangle of zero area (it covers no cell of its own).
inline bool PlaneOf(const CellTriangle& t, CellPlane* plane) {
  const double dc1 = t.col[1] - t.col[0], dr1 = t.row[1] - t.row[0];
  const double dc2 = t.col[2] - t.col[0], dr2 = t.row[2] - t.row[0];
  const double det = dc1 * dr2 - dc2 * dr1;
  if (det == 0) return false;
  const double dz1 = t.z[1] - t.z[0], dz2 = t.z[2] - t.z[0];
  plane->a = (dz1 * dr2 - dz2 * dr1) / det;
  plane->b = (dc1 * dz2 - dc2 * dz1) / det;
  plane->z0 = t.z[0];
  plane->c0 = t.col[0];
  plane->r0 = t.row[0];
  return true;
}

// The margin (1e-9 of a cell) by which ForEachCellSpan widens a triangle: it absorbs the rounding
// of world -> centre-space conversion, so a grid point that is a vertex is covered by its
// triangles.
inline constexpr double kCellSpanMargin = 1e-9;

// The first and last grid rows ForEachCellSpan may call `span` for (first > last: none).
inline std::pair<int64_t, int64_t> CellSpanRows(const CellTriangle& t, int64_t height) {
  const double lo = std::min({t.row[0], t.row[1], t.row[2]});
  const double hi = std::max({t.row[0], t.row[1], t.row[2]});
  return {std::max<int64_t>(0, static_cast<int64_t>(std::ceil(lo - kCellSpanMargin))),
          std::min<int64_t>(height - 1, static_cast<int64_t>(std::floor(hi + kCellSpanMargin)))};
}

// Calls span(row, first_col, last_col) for every grid row from row_min to row_max of cell centres
// inside or on `t` (within the margin), clipped to width x height. Splitting a triangle's rows
// (CellSpanRows) into ranges gives exactly the spans of the whole, range by range.
template <typename SpanFn>
void ForEachCellSpanInRows(const CellTriangle& t, int64_t width, int64_t height, int64_t row_min,
                           int64_t row_max, SpanFn&& span) {
  constexpr double kMargin = kCellSpanMargin;
  const auto [first_row, last_row] = CellSpanRows(t, height);
  row_min = std::max(row_min, first_row);
  row_max = std::min(row_max, last_row);
  for (int64_t r = row_min; r <= row_max; ++r) {
    double left = std::numeric_limits<double>::infinity();
    double right = -left;
    const double y = static_cast<double>(r);
    for (int e = 0; e < 3; ++e) {
      const double ac = t.col[e], ar = t.row[e];
      const double bc = t.col[(e + 1) % 3], br = t.row[(e + 1) % 3];
      if (y < std::min(ar, br) - kMargin || y > std::max(ar, br) + kMargin) continue;
      if (std::abs(br - ar) <= kMargin) {
        left = std::min({left, ac, bc});
        right = std::max({right, ac, bc});
        continue;
      }
      const double s = std::clamp((y - ar) / (br - ar), 0.0, 1.0);
      const double x = ac + s * (bc - ac);
      left = std::min(left, x);
      right = std::max(right, x);
    }
    if (!(left <= right)) continue;
    const int64_t first = std::max<int64_t>(0, static_cast<int64_t>(std::ceil(left - kMargin)));
    const int64_t last =
        std::min<int64_t>(width - 1, static_cast<int64_t>(std::floor(right + kMargin)));
    if (first <= last) span(r, first, last);
  }
}

// Calls span(row, first_col, last_col) for every grid row of cell centres inside or on `t`,
// clipped to width x height (ForEachCellSpanInRows over all its rows).
template <typename SpanFn>
void ForEachCellSpan(const CellTriangle& t, int64_t width, int64_t height, SpanFn&& span) {
  ForEachCellSpanInRows(t, width, height, 0, height - 1, std::forward<SpanFn>(span));
}

// Whether the centre of cell (col, row) lies inside or on the counter-clockwise triangle
// (a, b, c), exactly. ForEachCellSpan's margin also admits centres a rounding outside, where the
// plane is extrapolated: beside a ring a hair off a column of cell centres, a sliver's plane
// there can be metres from the surface, whose vertex at that very centre another triangle holds.
inline bool HoldsCellCentre(const GridGeometry& g, const TinVertex& a, const TinVertex& b,
                            const TinVertex& c, int64_t col, int64_t row) {
  const Point2 p{g.CellCenterX(col), g.CellCenterY(row)};
  return Orientation({a.x, a.y}, {b.x, b.y}, p) >= 0 &&
         Orientation({b.x, b.y}, {c.x, c.y}, p) >= 0 && Orientation({c.x, c.y}, {a.x, a.y}, p) >= 0;
}

// Indices 0..count-1 ordered by the tile (tile x tile cells, row by row) holding point_of(i), a
// world (x, y) pair clamped onto the grid: triangles visited in this order read a DEM streamed by
// blocks nearly in order instead of at random. Ties keep index order.
template <typename PointOf>
std::vector<size_t> InTileOrder(const GridGeometry& g, int64_t tile, size_t count,
                                PointOf point_of) {
  const int64_t tiles_across = (g.width + tile - 1) / tile;
  const auto clamped = [](double v, int64_t size) {
    return static_cast<int64_t>(std::clamp(v, 0.0, static_cast<double>(size - 1)));
  };
  std::vector<std::pair<int64_t, size_t>> keyed;
  keyed.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    const auto [x, y] = point_of(i);
    const int64_t col = clamped(g.ColumnAt(x), g.width), row = clamped(g.RowAt(y), g.height);
    keyed.emplace_back((row / tile) * tiles_across + col / tile, i);
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<size_t> order;
  order.reserve(count);
  for (const auto& [key, i] : keyed) order.push_back(i);
  return order;
}

// The cell containing the centroid of (a, b, c); false when the centroid is off the grid.
inline bool CentroidCell(const GridGeometry& g, const TinVertex& a, const TinVertex& b,
                         const TinVertex& c, int64_t* col, int64_t* row) {
  const double x = std::floor((((a.x + b.x + c.x) / 3) - g.origin_x) / g.cell_x);
  const double y = std::floor((((a.y + b.y + c.y) / 3) - g.origin_y) / g.cell_y);
  if (!(x >= 0 && y >= 0 && x < static_cast<double>(g.width) && y < static_cast<double>(g.height)))
    return false;
  *col = static_cast<int64_t>(x);
  *row = static_cast<int64_t>(y);
  return true;
}

// True when the cell containing the centroid of (a, b, c) holds data.
inline bool TriangleOnData(const Grid& dem, const TinVertex& a, const TinVertex& b,
                           const TinVertex& c) {
  int64_t col = 0, row = 0;
  return CentroidCell(dem.geometry, a, b, c, &col, &row) && dem.IsValid(col, row);
}

inline bool TriangleOnData(CellSource& dem, const TinVertex& a, const TinVertex& b,
                           const TinVertex& c) {
  int64_t col = 0, row = 0;
  return CentroidCell(dem.geometry(), a, b, c, &col, &row) && dem.IsValid(col, row);
}

template <typename Dem>
bool TriangleOnData(Dem& dem, const Tin& tin, const TinTriangle& t) {
  return TriangleOnData(dem, tin.vertices[t.v[0]], tin.vertices[t.v[1]], tin.vertices[t.v[2]]);
}

// True when every point of the box [x0, x1] x [y0, y1] lies in a cell holding data, so every
// triangle whose centroid lies in it is on data (the update engine's test for a whole block).
inline bool BoxOnData(const Grid& dem, double x0, double y0, double x1, double y1) {
  const GridGeometry& g = dem.geometry;
  const double ca = std::floor((x0 - g.origin_x) / g.cell_x);
  const double cb = std::floor((x1 - g.origin_x) / g.cell_x);
  const double ra = std::floor((y0 - g.origin_y) / g.cell_y);
  const double rb = std::floor((y1 - g.origin_y) / g.cell_y);
  const double c0 = std::min(ca, cb), c1 = std::max(ca, cb);
  const double r0 = std::min(ra, rb), r1 = std::max(ra, rb);
  if (!(c0 >= 0 && r0 >= 0 && c1 < static_cast<double>(g.width) &&
        r1 < static_cast<double>(g.height)))
    return false;
  for (auto row = static_cast<int64_t>(r0); row <= static_cast<int64_t>(r1); ++row)
    for (auto col = static_cast<int64_t>(c0); col <= static_cast<int64_t>(c1); ++col)
      if (!dem.IsValid(col, row)) return false;
  return true;
}

}  // namespace tinbase
