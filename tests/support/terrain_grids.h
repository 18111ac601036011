// Generated terrains and real-DEM windows for the TIN builder tests. Header-only; pure
// functions.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>

#include "core/raster/grid.h"

namespace tinbase::testing {

// A width x height grid with 10 m cells whose origin is away from zero (as real data is), cell
// values f(x, y) at the cell centres, x and y relative to the origin.
inline Grid MakeGrid(int64_t width, int64_t height,
                     const std::function<double(double, double)>& f) {
  Grid grid;
  grid.geometry = GridGeometry{500000.0, 5200000.0, 10.0, -10.0, width, height};
  grid.cells.resize(static_cast<size_t>(width * height));
  for (int64_t r = 0; r < height; ++r) {
    for (int64_t c = 0; c < width; ++c) {
      grid.cells[static_cast<size_t>(r * width + c)] = static_cast<float>(
          f(grid.geometry.CellCenterX(c) - 500000.0, grid.geometry.CellCenterY(r) - 5200000.0));
    }
  }
  return grid;
}

inline double Sines(double x, double y) {
  return 300 + 120 * std::sin(x / 170.0) * std::cos(y / 230.0) + 35 * std::sin((x + 2 * y) / 61.0);
}

// A random smooth terrain drawn from `rng`: a product of sines of random amplitude and
// wavelengths with per-cell noise, 2 to max_side cells a side. With probability hole_chance it has
// nodata patches; it may then hold no data at all (see AllNodata).
inline Grid RandomTerrain(std::mt19937& rng, int max_side, double hole_chance) {
  std::uniform_int_distribution<int> size(2, max_side);
  std::uniform_real_distribution<double> unit(0, 1);
  const double a = 200 * unit(rng), fx = 20 + 300 * unit(rng), fy = 20 + 300 * unit(rng);
  const double noise = 5 * unit(rng);
  const bool holes = unit(rng) < hole_chance;
  std::mt19937 cell_rng(rng());
  const int width = size(rng), height = size(rng);
  return MakeGrid(width, height, [&](double x, double y) {
    if (holes && std::sin(x / 37.0) * std::cos(y / 23.0) > 0.7)
      return std::numeric_limits<double>::quiet_NaN();
    return a * std::sin(x / fx) * std::cos(y / fy) + noise * unit(cell_rng);
  });
}

inline bool AllNodata(const Grid& grid) {
  return std::all_of(grid.cells.begin(), grid.cells.end(), [](float v) { return std::isnan(v); });
}

// The z the builders give a nodata corner cell (0, 0): the mean of the valid cells of the first
// square window [0, radius]^2 that holds any. REQUIRES: the grid holds valid cells.
inline double FirstValidWindowMean(const Grid& grid) {
  for (int64_t radius = 1;; ++radius) {
    double sum = 0;
    int count = 0;
    for (int64_t r = 0; r <= radius; ++r) {
      for (int64_t c = 0; c <= radius; ++c) {
        if (grid.IsValid(c, r)) sum += grid.At(c, r), ++count;
      }
    }
    if (count > 0) return sum / count;
  }
}

// The width x height window of `grid` whose top-left cell is (col, row), with its geometry.
// REQUIRES: the window lies inside the grid.
inline Grid Window(const Grid& grid, int64_t col, int64_t row, int64_t width, int64_t height) {
  Grid out;
  const GridGeometry& g = grid.geometry;
  out.geometry = GridGeometry{g.origin_x + static_cast<double>(col) * g.cell_x,
                              g.origin_y + static_cast<double>(row) * g.cell_y,
                              g.cell_x,
                              g.cell_y,
                              width,
                              height};
  out.crs_wkt = grid.crs_wkt;
  out.source_nodata = grid.source_nodata;
  out.cells.reserve(static_cast<size_t>(width * height));
  for (int64_t r = row; r < row + height; ++r) {
    for (int64_t c = col; c < col + width; ++c) out.cells.push_back(grid.At(c, r));
  }
  return out;
}

}  // namespace tinbase::testing
