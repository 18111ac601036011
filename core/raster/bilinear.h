// Bilinear interpolation over any cell accessor, with GDAL's conventions.
//
// The same function serves in-memory grids and the block-cached DEM store so both agree to the
// bit. Conventions follow GDAL's bilinear resampling, which tinbase is tested against: values
// stand at cell centres; within the outer half cell the edge cells are extended; a nodata (NaN)
// neighbour is left out and the remaining weights renormalised; NaN when all four are nodata or
// the point lies outside the grid.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/raster/grid_geometry.h"

namespace tinbase {

// CellFn: float(int64_t col, int64_t row), called only with in-range indices.
template <typename CellFn>
double SampleBilinear(const GridGeometry& g, double x, double y, CellFn&& cell) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  if (!g.Contains(x, y) || g.width == 0 || g.height == 0) return kNaN;
  const double fc = g.ColumnAt(x);
  const double fr = g.RowAt(y);
  const double c0f = std::floor(fc);
  const double r0f = std::floor(fr);
  const double tx = fc - c0f;
  const double ty = fr - r0f;
  const auto clamp_col = [&](int64_t c) { return std::clamp<int64_t>(c, 0, g.width - 1); };
  const auto clamp_row = [&](int64_t r) { return std::clamp<int64_t>(r, 0, g.height - 1); };
  const int64_t c0 = clamp_col(static_cast<int64_t>(c0f));
  const int64_t c1 = clamp_col(static_cast<int64_t>(c0f) + 1);
  const int64_t r0 = clamp_row(static_cast<int64_t>(r0f));
  const int64_t r1 = clamp_row(static_cast<int64_t>(r0f) + 1);
  const double w[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
  const double v[4] = {cell(c0, r0), cell(c1, r0), cell(c0, r1), cell(c1, r1)};
  double sum = 0;
  double weight = 0;
  for (int i = 0; i < 4; ++i) {
    if (std::isnan(v[i]) || w[i] == 0) continue;
    sum += w[i] * v[i];
    weight += w[i];
  }
  return weight == 0 ? kNaN : sum / weight;
}

}  // namespace tinbase
