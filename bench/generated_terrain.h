// The generated terrain of tinbase's benchmarks: deterministic, the same cells for every run and
// size up to 4097 (a larger grid extends a smaller one). Header-only; pure.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
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

}  // namespace tinbase
