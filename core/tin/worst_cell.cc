#include "core/tin/worst_cell.h"

#include <cmath>
#include <cstring>

namespace tinbase {
namespace {

// Four lanes in GCC/Clang vector extensions: two SSE2 registers, or one AVX2 register in the
// clone the loader picks on a CPU that has it.
using Doubles = double __attribute__((vector_size(32)));
using Floats = float __attribute__((vector_size(16)));
using Bits = int64_t __attribute__((vector_size(32)));

// |plane - cells[i]| at column x0 + i of the row whose term b (row - r0) is row_term:
// plane.At's sum, (z0 + a (c - c0)) + b (row - r0), with the row's term computed once.
inline double ErrorAt(const CellPlane& plane, double row_term, double x0, const float* cells,
                      int64_t i) {
  return std::fabs(plane.z0 + plane.a * (x0 + static_cast<double>(i) - plane.c0) + row_term -
                   static_cast<double>(cells[i]));
}

// The largest ErrorAt over cells[0..count); -1 when every cell is NaN. Each lane computes
// ErrorAt's expression in the same order of operations (x + 4 stays exact: integers far below
// 2^53), so the lanes give the same doubles as one cell at a time. fabs is the sign bit cleared,
// as std::fabs does. Errors are >= 0 or NaN, and NaN > best is false: NaN never wins.
inline double RunMaxError(const CellPlane& plane, double row_term, double x0, const float* cells,
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
    const double e = ErrorAt(plane, row_term, x0, cells, i);
    best = e > best ? e : best;
  }
  return best;
}

// Raises `worst` over cells[0..count), columns col .. col + count - 1 of `row`.
inline void RaiseToRunWorst(const CellPlane& plane, int64_t row, int64_t col, const float* cells,
                            int64_t count, WorstCell* worst) {
  const double row_term = plane.b * (static_cast<double>(row) - plane.r0);
  const double x0 = static_cast<double>(col);
  const double best = RunMaxError(plane, row_term, x0, cells, count);
  if (!(best > worst->error)) return;
  // The same expression gives the same double: the search always stops at a cell of this run.
  int64_t i = 0;
  while (i + 1 < count && ErrorAt(plane, row_term, x0, cells, i) != best) ++i;
  *worst = WorstCell{best, col + i, row};
}

// The scan over one kind of source, run by run as CellSource::ForEachRun reads them; Source is
// named so that a GridCellSource's Span (a final class) is called directly, inlined.
template <typename Source>
inline void ScanRows(Source& dem, const CellTriangle& t, const CellPlane& plane, int64_t row_min,
                     int64_t row_max, WorstCell* worst) {
  const GridGeometry& g = dem.geometry();
  ForEachCellSpanInRows(t, g.width, g.height, row_min, row_max,
                        [&](int64_t row, int64_t first, int64_t last) {
                          for (int64_t col = first; col <= last;) {
                            int64_t end = last;
                            const float* cells = dem.Span(row, col, &end);
                            RaiseToRunWorst(plane, row, col, cells, end - col + 1, worst);
                            col = end + 1;
                          }
                        });
}

}  // namespace

// The scan is cloned for AVX2, picked at load time by an ifunc resolver. ThreadSanitizer
// instruments that resolver, which the dynamic loader runs before TSan's runtime has started: the
// program crashes before main. Under TSan there is one plain version, and under clang (which
// clang-tidy parses with) too: clang does not combine target_clones with flatten.
#if defined(__SANITIZE_THREAD__) || defined(__clang__)
#define TINBASE_CLONED_FOR_AVX2
#else
#define TINBASE_CLONED_FOR_AVX2 target_clones("avx2", "default"),
#endif

__attribute__((TINBASE_CLONED_FOR_AVX2 flatten)) void RaiseToWorstInRows(
    CellSource& dem, const CellTriangle& t, const CellPlane& plane, int64_t row_min,
    int64_t row_max, WorstCell* worst) {
  if (auto* grid = dynamic_cast<GridCellSource*>(&dem)) {
    ScanRows(*grid, t, plane, row_min, row_max, worst);
  } else {
    ScanRows(dem, t, plane, row_min, row_max, worst);
  }
}

}  // namespace tinbase
