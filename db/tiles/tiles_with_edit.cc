// The tile update run as an edit's before-commit hook.
#include "db/tiles/tiles_with_edit.h"

#include <algorithm>

namespace tinbase {

namespace {

// Adds one edit's update of a surface to the running total of that surface.
void AddUp(TileUpdates& total, const SurfaceInfo& surface, const TileUpdateReport& report) {
  const auto same = [&](const auto& entry) { return entry.first.id == surface.id; };
  const auto it = std::find_if(total.begin(), total.end(), same);
  if (it == total.end()) {
    total.emplace_back(surface, report);
    return;
  }
  TileUpdateReport& sum = it->second;
  sum.tx = report.tx;
  sum.changes += report.changes;
  sum.full_rebuild = sum.full_rebuild || report.full_rebuild;
  sum.tiles_meeting += report.tiles_meeting;
  sum.tiles_rewritten += report.tiles_rewritten;
  sum.tiles_deleted += report.tiles_deleted;
  sum.read_seconds += report.read_seconds;
  sum.make_seconds += report.make_seconds;
  sum.write_seconds += report.write_seconds;
}

}  // namespace

std::function<Status(Store& store, int64_t tx)> UpdateTilesBeforeCommit(TileUpdates* updates) {
  return [updates](Store& store, int64_t /*tx*/) -> Status {
    auto updated = UpdateAllTilePyramids(store);
    if (!updated.ok()) return updated.status().WithContext("updating the tiles of the edit");
    for (const auto& [surface, report] : *updated) AddUp(*updates, surface, report);
    return Status::Ok();
  };
}

int64_t TilesTouched(const TileUpdates& updates) {
  int64_t tiles = 0;
  for (const auto& entry : updates)
    tiles += entry.second.tiles_rewritten + entry.second.tiles_deleted;
  return tiles;
}

}  // namespace tinbase
