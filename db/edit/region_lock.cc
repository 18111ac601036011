#include "db/edit/region_lock.h"

#include <algorithm>

namespace tinbase {

std::vector<int64_t> BlocksToLock(const BlockGrid& grid, const Box& box) {
  std::vector<int64_t> blocks;
  if (box.empty()) return blocks;
  const int64_t x0 = std::max<int64_t>(grid.ColumnOf(box.min_x) - 1, 0);
  const int64_t y0 = std::max<int64_t>(grid.RowOf(box.min_y) - 1, 0);
  const int64_t x1 = std::min(grid.ColumnOf(box.max_x) + 1, BlockGrid::kStride - 1);
  const int64_t y1 = std::min(grid.RowOf(box.max_y) + 1, BlockGrid::kStride - 1);
  if ((x1 - x0 + 1) * (y1 - y0 + 1) > static_cast<int64_t>(kMaxLockedBlocks)) return blocks;
  for (int64_t by = y0; by <= y1; ++by)
    for (int64_t bx = x0; bx <= x1; ++bx) blocks.push_back(BlockGrid::Pack(bx, by));
  return blocks;
}

Status LockEditRegion(Connection& db, int64_t surface, const BlockGrid& grid, const Box& box,
                      const std::vector<int64_t>& also, bool whole_surface) {
  if (!db.ConcurrentWriters()) return Status::Ok();
  std::vector<int64_t> blocks;
  if (!whole_surface) blocks = BlocksToLock(grid, box);
  if (!blocks.empty()) blocks.insert(blocks.end(), also.begin(), also.end());
  if (blocks.size() > kMaxLockedBlocks) blocks.clear();
  return db.LockRegion(surface, blocks, whole_surface || blocks.empty())
      .WithContext("locking the edit's region");
}

}  // namespace tinbase
