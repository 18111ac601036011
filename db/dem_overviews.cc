// The overview levels of a DEM: how many there are, and recomputing them above the level-0 blocks
// an import wrote (each cell the mean of the valid cells of the 2 x 2 below it).
#include <cmath>

#include "db/dem_store.h"
#include "db/dem_store_impl.h"
#include "db/sql/each_row.h"

namespace tinbase {

using dem_internal::FloorDiv;
using dem_internal::kNaN;

namespace dem_internal {

// Levels until one block holds the whole level: each level halves the one below.
int LevelCount(const DemInfo& dem) {
  constexpr int kMaxLevels = 31;
  for (int level = 0; level + 1 < kMaxLevels; ++level) {
    const DemLevel lv = LevelOf(dem, level);
    const int64_t b = dem.block_size;
    const bool one_column =
        FloorDiv(-lv.block_col0, b) == FloorDiv(lv.geometry.width - 1 - lv.block_col0, b);
    const bool one_row =
        FloorDiv(-lv.block_row0, b) == FloorDiv(lv.geometry.height - 1 - lv.block_row0, b);
    if (one_column && one_row) return level + 1;
  }
  return kMaxLevels;
}

}  // namespace dem_internal

namespace {

// The parent cells of four child blocks (nullptr: not stored): each the mean of the valid cells of
// the 2 x 2 below it. children[dy * 2 + dx] is child (2 bx + dx, 2 by + dy).
std::vector<float> Downsample(const std::vector<float>* const children[4], int64_t b) {
  std::vector<float> parent(static_cast<size_t>(b * b), kNaN);
  const int64_t half = b / 2;
  for (int64_t r = 0; r < b; ++r) {
    for (int64_t c = 0; c < b; ++c) {
      const std::vector<float>* child = children[(r / half) * 2 + c / half];
      if (child == nullptr) continue;
      const int64_t cr = (r % half) * 2;
      const int64_t cc = (c % half) * 2;
      double sum = 0;
      int valid = 0;
      for (int64_t dr = 0; dr < 2; ++dr)
        for (int64_t dc = 0; dc < 2; ++dc) {
          const float v = (*child)[static_cast<size_t>((cr + dr) * b + cc + dc)];
          if (std::isnan(v)) continue;
          sum += v;
          ++valid;
        }
      if (valid > 0) parent[static_cast<size_t>(r * b + c)] = static_cast<float>(sum / valid);
    }
  }
  return parent;
}

}  // namespace

Status DemStore::Impl::UpdateOverviews(const DemInfo& dem, int old_levels,
                                       std::set<std::pair<int64_t, int64_t>> touched,
                                       DemImportReport* report) {
  for (int level = 1; level < dem.levels; ++level) {
    if (level >= old_levels) {  // a new level: every block of the level below has a parent here
      touched.clear();
      TB_ASSIGN_OR_RETURN(Statement * all, store.db().Cached("SELECT bx, by FROM dem_blocks "
                                                             "WHERE dem = ? AND level = ?"));
      all->Bind(1, dem.id).Bind(2, static_cast<int64_t>(level - 1));
      TB_RETURN_IF_ERROR(EachRow(
          *all, [&](Statement& row) { touched.emplace(row.ColumnInt(1), row.ColumnInt(0)); }));
    }
    std::set<std::pair<int64_t, int64_t>> parents;
    for (const auto& [by, bx] : touched) parents.emplace(FloorDiv(by, 2), FloorDiv(bx, 2));
    for (const auto& [by, bx] : parents) {
      Block children[4];
      const std::vector<float>* cells[4];
      for (int i = 0; i < 4; ++i) {
        TB_ASSIGN_OR_RETURN(children[i], LoadBlock(dem, level - 1, 2 * bx + i % 2, 2 * by + i / 2));
        cells[i] = children[i].get();
      }
      TB_RETURN_IF_ERROR(WriteBlock(dem, level, bx, by, Downsample(cells, dem.block_size), report));
    }
    touched = std::move(parents);
  }
  return Status::Ok();
}

}  // namespace tinbase
