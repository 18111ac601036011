// The generated terrains of tinbase's benchmarks: deterministic, the same cells for every run and
// size up to 4097 (a larger grid extends a smaller one, save for the rough terrain's rescaling).
// Header-only; pure.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "core/raster/grid.h"

namespace tinbase {

// Value noise: a lattice of random heights every `period` cells, smoothly interpolated.
class ValueNoise {
 public:
  ValueNoise(int64_t size, int64_t period, uint32_t seed) : period_(period), n_(size / period + 2) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(-1, 1);
    lattice_.resize(static_cast<size_t>(n_ * n_));
    for (double& v : lattice_) v = unit(rng);
  }
  double At(int64_t col, int64_t row) const {
    const double x = static_cast<double>(col) / period_, y = static_cast<double>(row) / period_;
    const auto i = static_cast<int64_t>(x), j = static_cast<int64_t>(y);
    const double fx = Smooth(x - i), fy = Smooth(y - j);
    const auto v = [&](int64_t a, int64_t b) { return lattice_[static_cast<size_t>(b * n_ + a)]; };
    return (v(i, j) * (1 - fx) + v(i + 1, j) * fx) * (1 - fy) +
           (v(i, j + 1) * (1 - fx) + v(i + 1, j + 1) * fx) * fy;
  }

 private:
  static double Smooth(double t) { return t * t * (3 - 2 * t); }
  int64_t period_;
  int64_t n_;
  std::vector<double> lattice_;
};

// The generated terrain: 1 m cells, octaves of value noise from 1024 cells down to 2 with the
// amplitude halving each octave (a fractal surface of dimension ~2.0, like eroded hills), ~0 to
// 1500 m, plus a ridge line; the same for every size (a larger one extends a smaller one).
inline Grid GeneratedTerrain(int64_t size) {
  Grid grid;
  grid.geometry = GridGeometry{500000, 5200000, 1, -1, size, size};
  grid.cells.assign(static_cast<size_t>(size * size), 0);
  double amplitude = 600;
  uint32_t seed = 1;
  for (int64_t period = 1024; period >= 2; period /= 2, amplitude /= 2, ++seed) {
    const ValueNoise noise(std::max<int64_t>(size, 4097), period, seed);
    for (int64_t r = 0; r < size; ++r)
      for (int64_t c = 0; c < size; ++c)
        grid.cells[static_cast<size_t>(r * size + c)] +=
            static_cast<float>(amplitude * noise.At(c, r));
  }
  for (int64_t r = 0; r < size; ++r)
    for (int64_t c = 0; c < size; ++c)
      grid.cells[static_cast<size_t>(r * size + c)] +=
          static_cast<float>(700 - 0.1 * std::abs(static_cast<double>(c - r)));
  return grid;
}

// Issue 30's rough terrain: fractional Brownian motion (octaves of value noise from 2048 cells
// down to 2, amplitude proportional to the period, so a Hurst exponent of 1), rescaled to 0 to
// 2000 m, plus white sensor noise of 0.3 m standard deviation, then quantised to the 65536 levels
// of a 16-bit PNG over its range, so hmm (which reads 16-bit PNGs) and every other tool see the
// same cells. 30 m cells. Returns the grid and the size of one level in metres.
inline std::pair<Grid, double> RoughTerrain(int64_t size) {
  Grid grid;
  grid.geometry = GridGeometry{500000, 5200000, 30, -30, size, size};
  std::vector<double> z(static_cast<size_t>(size * size), 0);
  uint32_t seed = 101;
  for (int64_t period = 2048; period >= 2; period /= 2, ++seed) {
    const ValueNoise noise(std::max<int64_t>(size, 4097), period, seed);
    const auto amplitude = static_cast<double>(period);
    for (int64_t r = 0; r < size; ++r)
      for (int64_t c = 0; c < size; ++c)
        z[static_cast<size_t>(r * size + c)] += amplitude * noise.At(c, r);
  }
  const auto [lo, hi] = std::minmax_element(z.begin(), z.end());
  const double low = *lo, scale = 2000 / (*hi - *lo);
  std::mt19937_64 rng(30);
  std::normal_distribution<double> sensor(0, 0.3);
  for (double& v : z) v = (v - low) * scale + sensor(rng);
  const auto [lo2, hi2] = std::minmax_element(z.begin(), z.end());
  const double base = *lo2, step = (*hi2 - *lo2) / 65535;
  grid.cells.resize(z.size());
  for (size_t i = 0; i < z.size(); ++i)
    grid.cells[i] = static_cast<float>(std::round((z[i] - base) / step) * step);
  return {std::move(grid), step};
}

}  // namespace tinbase
