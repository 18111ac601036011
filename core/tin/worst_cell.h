// WorstCell: where a face's plane is furthest from the DEM, the inner loop of greedy refinement
// (core/tin/tolerance_refiner.h) and most of its time on coarse tolerances, where the first faces
// span the whole grid and every insertion rescans millions of cells.
//
// A run of contiguous cells is first reduced to its largest error without a branch per cell (four
// independent maxima the compiler can keep in vector registers); only a run whose maximum beats
// the worst so far is walked again for the first cell that has it. The errors are computed by the
// same double expression in both passes (CellPlane::At, no contraction: -ffp-contract=off), so
// the cell found is exactly the one a cell-by-cell scan keeping the first strict maximum finds.
// Thread-safety: pure functions of their arguments; the CellSource is read by the calling thread.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/raster/cell_source.h"
#include "core/tin/cell_cover.h"

namespace tinbase {

// A worst cell so far: `error` starts at the floor (the tolerance) that a cell must strictly
// exceed to count; col and row stay -1 until one does.
struct WorstCell {
  double error = 0;
  int64_t col = -1, row = -1;
};

// The largest |plane - cell| over cells[0..count), columns x0 .. x0 + count - 1 of the row whose
// term b (row - r0) is row_term; -1 when every cell is NaN. Vectorised, on AVX2 where the CPU has
// it (the same IEEE operations on each lane, so the same doubles as one at a time).
double RunMaxError(const CellPlane& plane, double row_term, double x0, const float* cells,
                   int64_t count);

// Raises `worst` to the largest |plane - cell| over cells[0..count), which are columns col ..
// col + count - 1 of `row`, at the first cell with that error, when it exceeds worst->error.
// NaN cells (nodata) never count.
inline void RaiseToRunWorst(const CellPlane& plane, int64_t row, int64_t col, const float* cells,
                            int64_t count, WorstCell* worst) {
  // plane.At(c, row) is (z0 + a (c - c0)) + b (row - r0): the row's term once, the same sum.
  const double row_term = plane.b * (static_cast<double>(row) - plane.r0);
  // x is a column as a double; columns are far below 2^53, so x0 + i is exact.
  const double x0 = static_cast<double>(col);
  const auto error_at = [&](int64_t i) {
    return std::fabs(plane.z0 + plane.a * (x0 + static_cast<double>(i) - plane.c0) + row_term -
                     static_cast<double>(cells[i]));
  };
  // Short runs (small faces, fine tolerances) are not worth a call: one at a time. Errors are
  // >= 0 or NaN, and NaN > best is false: -1 is "none yet" and NaN never wins.
  constexpr int64_t kShortRun = 16;
  double best = -1;
  if (count < kShortRun) {
    for (int64_t i = 0; i < count; ++i) {
      const double e = error_at(i);
      best = e > best ? e : best;
    }
  } else {
    best = RunMaxError(plane, row_term, x0, cells, count);
  }
  if (!(best > worst->error)) return;
  // The same expression gives the same double: the search always stops at a cell of this run.
  int64_t i = 0;
  while (i + 1 < count && error_at(i) != best) ++i;
  *worst = WorstCell{best, col + i, row};
}

// Raises `worst` over the cells of t's spans (ForEachCellSpanInRows) in rows row_min..row_max,
// scanned row by row and left to right: the first cell with the largest error wins.
inline void RaiseToWorstInRows(CellSource& dem, const CellTriangle& t, const CellPlane& plane,
                               int64_t row_min, int64_t row_max, WorstCell* worst) {
  const GridGeometry& g = dem.geometry();
  ForEachCellSpanInRows(
      t, g.width, g.height, row_min, row_max, [&](int64_t row, int64_t first, int64_t last) {
        dem.ForEachRun(row, first, last, [&](int64_t col, const float* cells, int64_t count) {
          RaiseToRunWorst(plane, row, col, cells, count, worst);
        });
      });
}

}  // namespace tinbase
