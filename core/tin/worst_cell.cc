#include "core/tin/worst_cell.h"

#include <cstring>

namespace tinbase {
namespace {

// Four lanes in GCC/Clang vector extensions: two SSE2 registers, or one AVX2 register in the
// clone the loader picks on a CPU that has it.
using Doubles = double __attribute__((vector_size(32)));
using Floats = float __attribute__((vector_size(16)));
using Bits = int64_t __attribute__((vector_size(32)));

}  // namespace

// Each lane computes error_at of RaiseToRunWorst in the same order of operations; x + 4 stays
// exact (integers far below 2^53). fabs is the sign bit cleared, as std::fabs does.
__attribute__((target_clones("avx2", "default"))) double RunMaxError(const CellPlane& plane,
                                                                     double row_term, double x0,
                                                                     const float* cells,
                                                                     int64_t count) {
  const Doubles z0 = Doubles{} + plane.z0, a = Doubles{} + plane.a, c0 = Doubles{} + plane.c0;
  const Doubles term = Doubles{} + row_term;
  const Bits magnitude = Bits{} + INT64_MAX;
  Doubles x = Doubles{0, 1, 2, 3} + x0;
  Doubles m = Doubles{} - 1;
  int64_t i = 0;
  for (; i + 4 <= count; i += 4, x += 4) {
    Floats f;
    std::memcpy(&f, cells + i, sizeof f);
    const Doubles diff = z0 + a * (x - c0) + term - __builtin_convertvector(f, Doubles);
    const Doubles e = reinterpret_cast<Doubles>(reinterpret_cast<Bits>(diff) & magnitude);
    m = e > m ? e : m;
  }
  double best = -1;
  for (int k = 0; k < 4; ++k) best = m[k] > best ? m[k] : best;
  for (; i < count; ++i) {
    const double e = std::fabs(plane.z0 + plane.a * (x0 + static_cast<double>(i) - plane.c0) +
                               row_term - static_cast<double>(cells[i]));
    best = e > best ? e : best;
  }
  return best;
}

}  // namespace tinbase
