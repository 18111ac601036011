// DemCellSource: a stored DEM's level-0 cells as a CellSource (core/raster/cell_source.h), read
// block by block, so builders and checkers scan DEMs far larger than memory.
//
// Blocks come through the process-wide block cache (db/dem_block_cache.h), whose memory limit
// bounds what stays decoded; the source itself pins only the few dozen blocks it used last, so a
// scan that walks back and forth over a block edge costs no cache lookups. A block that cannot
// be read reads as NaN and status() reports the first such error (Corruption naming the block
// when its bytes do not decode); callers must return that error, not take the NaN for nodata.
// Thread-safety: one thread at a time; holds references to the DemStore and the DemInfo's copy.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/raster/cell_source.h"
#include "db/dem_store.h"

namespace tinbase {

class DemCellSource final : public CellSource {
 public:
  DemCellSource(DemStore& dems, DemInfo dem);

  const GridGeometry& geometry() const override { return dem_.geometry; }
  const float* Span(int64_t row, int64_t col, int64_t* last) override;
  Status status() const override { return status_; }

 private:
  using Block = std::shared_ptr<const std::vector<float>>;
  struct Slot {
    int64_t bx = 0, by = 0;
    bool used = false;
    Block block;
  };
  static constexpr size_t kSlots = 64;

  // The cells of block (bx, by), or null when it holds no data or cannot be read.
  const float* BlockCells(int64_t bx, int64_t by);

  DemStore& dems_;
  const DemInfo dem_;
  const int shift_;  // log2 of the block size
  const int64_t mask_;
  std::array<Slot, kSlots> slots_;
  const Slot* last_ = nullptr;
  std::vector<float> nodata_row_;  // one block row of NaN, for blocks with no data
  Status status_;
};

}  // namespace tinbase
