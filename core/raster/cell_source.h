// CellSource: read access to a DEM's cells one row span at a time, whether the grid is in memory
// (GridCellSource) or streamed block by block from a store (db/dem_cell_source.h), so the TIN
// builders and checkers that scan cells under triangles work on DEMs larger than memory.
//
// Callers ask for a span of one row and get a pointer to as much of it as lies contiguous in
// memory (to the edge of a block), then ask again for the rest. A streamed source cannot fail
// in the middle of a scan without making every caller error-aware in its inner loop, so it is
// sticky instead (as LevelDB's iterators): a block that cannot be read reads as NaN and status()
// reports the first error. Callers check status() when they finish and, when it is not OK,
// return it and drop what they computed: a failed read is an error (Corruption, IOError), never
// "no data here".
// Thread-safety: a source is used by one thread at a time.
#pragma once

#include <cstdint>

#include "core/base/status.h"
#include "core/raster/grid.h"
#include "core/raster/grid_geometry.h"

namespace tinbase {

class CellSource {
 public:
  virtual ~CellSource() = default;

  virtual const GridGeometry& geometry() const = 0;

  // A pointer to cell (col, row) from which cells col..*last of the row are contiguous; *last is
  // lowered to the end of what is contiguous. NaN = nodata. Valid until the next call.
  // REQUIRES: 0 <= col <= *last < width, 0 <= row < height.
  virtual const float* Span(int64_t row, int64_t col, int64_t* last) = 0;

  // The first error met reading cells (those cells read as nodata); OK when none.
  virtual Status status() const { return Status::Ok(); }

  // Whether two threads may call Span at once (a grid in memory: nothing changes on a read).
  virtual bool ConcurrentReads() const { return false; }

  float At(int64_t col, int64_t row) {
    int64_t last = col;
    return *Span(row, col, &last);
  }
  bool IsValid(int64_t col, int64_t row) { return !std::isnan(At(col, row)); }

  // Calls fn(col, cells, count) for each contiguous run of row `row` from `first` to `last`:
  // cells[0..count) are columns col..col + count - 1.
  template <typename RunFn>
  void ForEachRun(int64_t row, int64_t first, int64_t last, RunFn&& fn) {
    for (int64_t c = first; c <= last;) {
      int64_t end = last;
      const float* cells = Span(row, c, &end);
      fn(c, cells, end - c + 1);
      c = end + 1;
    }
  }

  // Calls fn(col, value) for every cell of row `row` from `first` to `last`, span by span.
  template <typename CellFn>
  void ForEachCell(int64_t row, int64_t first, int64_t last, CellFn&& fn) {
    ForEachRun(row, first, last, [&](int64_t col, const float* cells, int64_t count) {
      for (int64_t i = 0; i < count; ++i) fn(col + i, cells[i]);
    });
  }
};

// A Grid in memory as a CellSource: every row is one span. Holds a reference to the grid.
class GridCellSource final : public CellSource {
 public:
  explicit GridCellSource(const Grid& grid) : grid_(grid) {}

  const GridGeometry& geometry() const override { return grid_.geometry; }
  const float* Span(int64_t row, int64_t col, int64_t* /*last*/) override {
    return grid_.cells.data() + row * grid_.geometry.width + col;
  }
  bool ConcurrentReads() const override { return true; }

 private:
  const Grid& grid_;
};

}  // namespace tinbase
