#include "db/dem_cell_source.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <utility>

namespace tinbase {

DemCellSource::DemCellSource(DemStore& dems, DemInfo dem)
    : dems_(dems),
      dem_(std::move(dem)),
      shift_(std::countr_zero(static_cast<unsigned>(dem_.block_size))),
      mask_(dem_.block_size - 1),
      nodata_row_(static_cast<size_t>(dem_.block_size), std::numeric_limits<float>::quiet_NaN()) {}

const float* DemCellSource::Span(int64_t row, int64_t col, int64_t* last) {
  const int64_t c = col - dem_.block_col0;
  const int64_t r = row - dem_.block_row0;
  // Block sizes are powers of two: an arithmetic shift is floor division, also west of the
  // anchor.
  const int64_t bx = c >> shift_, by = r >> shift_;
  *last = std::min(*last, dem_.block_col0 + ((bx + 1) << shift_) - 1);
  const float* cells = BlockCells(bx, by);
  if (cells == nullptr) return nodata_row_.data();
  return cells + ((r & mask_) << shift_) + (c & mask_);
}

const float* DemCellSource::BlockCells(int64_t bx, int64_t by) {
  if (last_ == nullptr || last_->bx != bx || last_->by != by) {
    const size_t hash = static_cast<size_t>(bx * 73856093 ^ by * 19349663) % kSlots;
    Slot& slot = slots_[hash];
    if (!slot.used || slot.bx != bx || slot.by != by) {
      auto block = dems_.ReadBlock(dem_, 0, bx, by);
      if (!block.ok() && status_.ok()) status_ = block.status();
      slot = Slot{bx, by, true, block.ok() ? std::move(block).value() : nullptr};
    }
    last_ = &slot;
  }
  return last_->block ? last_->block->data() : nullptr;
}

}  // namespace tinbase
