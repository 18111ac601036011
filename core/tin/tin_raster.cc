#include "core/tin/tin_raster.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tinbase {

namespace {

// The TIN's z at every cell centre in double precision: the error measure must not round to
// float32 (about 6e-5 m at 1000 m), or a stored tolerance made from it would fail the checker.
std::vector<double> TinAtCellCentres(const Tin& tin, const GridGeometry& g) {
  std::vector<double> cells(static_cast<size_t>(g.CellCount()),
                            std::numeric_limits<double>::quiet_NaN());
  if (g.width <= 0 || g.height <= 0) return cells;
  for (const TinTriangle& t : tin.triangles) {
    const TinVertex& p0 = tin.vertices[t.v[0]];
    const TinVertex& p1 = tin.vertices[t.v[1]];
    const TinVertex& p2 = tin.vertices[t.v[2]];
    // Coordinates relative to p0: map coordinates in the millions would otherwise cost the
    // determinant most of its digits.
    const double ax = p1.x - p0.x, ay = p1.y - p0.y;
    const double bx = p2.x - p0.x, by = p2.y - p0.y;
    const double det = ax * by - bx * ay;
    if (det == 0) continue;
    const double c_lo = g.ColumnAt(std::min({p0.x, p1.x, p2.x}));
    const double c_hi = g.ColumnAt(std::max({p0.x, p1.x, p2.x}));
    const double r_a = g.RowAt(p0.y), r_b = g.RowAt(p1.y), r_c = g.RowAt(p2.y);
    const int64_t c0 = std::max<int64_t>(0, static_cast<int64_t>(std::ceil(std::min(c_lo, c_hi))));
    const int64_t c1 =
        std::min<int64_t>(g.width - 1, static_cast<int64_t>(std::floor(std::max(c_lo, c_hi))));
    const int64_t r0 =
        std::max<int64_t>(0, static_cast<int64_t>(std::ceil(std::min({r_a, r_b, r_c}))));
    const int64_t r1 = std::min<int64_t>(
        g.height - 1, static_cast<int64_t>(std::floor(std::max({r_a, r_b, r_c}))));
    // A centre exactly on an edge must land in one of the two triangles; 1e-12 of the
    // barycentric range is far below a cell and far above the round-off of these few products.
    constexpr double kEdgeSlack = 1e-12;
    for (int64_t r = r0; r <= r1; ++r) {
      const double y = g.CellCenterY(r) - p0.y;
      for (int64_t c = c0; c <= c1; ++c) {
        const double x = g.CellCenterX(c) - p0.x;
        const double l1 = (x * by - bx * y) / det;
        const double l2 = (ax * y - x * ay) / det;
        const double l0 = 1 - l1 - l2;
        if (l0 < -kEdgeSlack || l1 < -kEdgeSlack || l2 < -kEdgeSlack) continue;
        cells[static_cast<size_t>(r * g.width + c)] = l0 * p0.z + l1 * p1.z + l2 * p2.z;
      }
    }
  }
  return cells;
}

}  // namespace

std::vector<float> RasteriseTin(const Tin& tin, const GridGeometry& g) {
  const std::vector<double> z = TinAtCellCentres(tin, g);
  return std::vector<float>(z.begin(), z.end());
}

TinGridError CompareTinToGrid(const Tin& tin, const Grid& grid) {
  const std::vector<double> z = TinAtCellCentres(tin, grid.geometry);
  TinGridError error;
  double sum_sq = 0;
  for (size_t i = 0; i < grid.cells.size(); ++i) {
    if (std::isnan(grid.cells[i])) continue;
    if (std::isnan(z[i])) {
      ++error.uncovered;
      continue;
    }
    const double d = z[i] - grid.cells[i];
    error.max_error = std::max(error.max_error, std::fabs(d));
    sum_sq += d * d;
    ++error.cells;
  }
  if (error.cells > 0) error.rms_error = std::sqrt(sum_sq / static_cast<double>(error.cells));
  return error;
}

}  // namespace tinbase
