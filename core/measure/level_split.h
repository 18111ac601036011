// LevelSplit: where a linear function over a triangle is positive and where negative, exactly.
//
// Volume above a level and cut/fill between two surfaces both come down to one question per
// plane triangle: given the heights d0, d1, d2 of a linear function at the corners (z - level, or
// top - base), how much lies above zero and how much below? The zero line cuts the triangle into
// a triangle and a quadrilateral; the part on the single corner's side is a triangle similar in
// plan to a corner of the original, scaled by d_i / (d_i - d_j) along each edge, so its area is
// A d_i^2 / ((d_i - d_j)(d_i - d_k)) and its volume (a pyramid over it) a third of that times d_i.
// The other side follows from the totals A and A (d0 + d1 + d2) / 3. No square roots, no
// cancellation beyond the differences themselves. Pure functions.
#pragma once

#include <array>

namespace tinbase {

struct SplitMeasure {
  double above_volume = 0;  // integral of max(d, 0)
  double below_volume = 0;  // integral of max(-d, 0), positive
  double above_area = 0;    // plan area where d > 0
  double below_area = 0;    // plan area where d < 0
  SplitMeasure& operator+=(const SplitMeasure& o) {
    above_volume += o.above_volume, below_volume += o.below_volume;
    above_area += o.above_area, below_area += o.below_area;
    return *this;
  }
};

// The split of a triangle of plan area `area` with corner values `d`.
// REQUIRES: area >= 0; d finite.
SplitMeasure SplitTriangle(double area, const std::array<double, 3>& d);

}  // namespace tinbase
