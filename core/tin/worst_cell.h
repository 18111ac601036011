// WorstCell: where a face's plane is furthest from the DEM, the inner loop of greedy refinement
// (core/tin/tolerance_refiner.h) and most of its time on coarse tolerances, where the first faces
// span the whole grid and every insertion rescans millions of cells.
//
// A run of contiguous cells is first reduced to its largest error without a branch per cell (four
// independent maxima the compiler can keep in vector registers); only a run whose maximum beats
// the worst so far is walked again for the first cell that has it. The errors are computed by the
// same double expression in both passes (CellPlane::At, no contraction: -ffp-contract=off), so
// the cell found is exactly the one a cell-by-cell scan keeping the first strict maximum finds.
// A face's rows are scanned in one call, compiled for AVX2 where the CPU has it: on coarse
// tolerances rows are a few dozen cells, and a call per row (its setup, a virtual read of the
// span) cost more than reading the row's cells.
// Thread-safety: pure functions of their arguments; the CellSource is read by the calling thread.
#pragma once

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

// Raises `worst` to the largest |plane - cell| over the cells of t's spans
// (ForEachCellSpanInRows) in rows row_min..row_max, at the first cell with that error scanning
// row by row and left to right, when it exceeds worst->error. NaN cells (nodata) never count.
void RaiseToWorstInRows(CellSource& dem, const CellTriangle& t, const CellPlane& plane,
                        int64_t row_min, int64_t row_max, WorstCell* worst);

}  // namespace tinbase
