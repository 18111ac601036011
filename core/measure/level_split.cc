#include "core/measure/level_split.h"

namespace tinbase {

namespace {

// The positive part's volume and area when only d[i] is positive: the corner triangle at i.
// REQUIRES: d[i] > 0 >= the other two.
void LonePositive(double area, const std::array<double, 3>& d, int i, double* volume,
                  double* part_area) {
  const double di = d[i];
  const double dj = d[(i + 1) % 3];
  const double dk = d[(i + 2) % 3];
  const double share = di * di / ((di - dj) * (di - dk));
  *part_area = area * share;
  *volume = *part_area * di / 3;
}

// Volume and area where d > 0.
void PositivePart(double area, const std::array<double, 3>& d, double* volume, double* part_area) {
  int positive = 0;
  for (double v : d) positive += v > 0 ? 1 : 0;
  if (positive == 0) {
    *volume = 0, *part_area = 0;
    return;
  }
  int zero_or_less = 0;
  for (int i = 0; i < 3; ++i) {
    if (d[i] <= 0) zero_or_less = i;
  }
  if (positive == 3) {
    *volume = area * (d[0] + d[1] + d[2]) / 3, *part_area = area;
    return;
  }
  if (positive == 1) {
    for (int i = 0; i < 3; ++i) {
      if (d[i] > 0) LonePositive(area, d, i, volume, part_area);
    }
    return;
  }
  // Two positive: the whole minus the lone non-positive corner's part of -d (which is zero when
  // that corner is exactly zero).
  const std::array<double, 3> minus{-d[0], -d[1], -d[2]};
  double neg_volume = 0;
  double neg_area = 0;
  if (minus[zero_or_less] > 0) LonePositive(area, minus, zero_or_less, &neg_volume, &neg_area);
  *volume = area * (d[0] + d[1] + d[2]) / 3 + neg_volume;
  *part_area = area - neg_area;
}

}  // namespace

SplitMeasure SplitTriangle(double area, const std::array<double, 3>& d) {
  SplitMeasure out;
  PositivePart(area, d, &out.above_volume, &out.above_area);
  PositivePart(area, {-d[0], -d[1], -d[2]}, &out.below_volume, &out.below_area);
  return out;
}

}  // namespace tinbase
