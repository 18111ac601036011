// The edit commands' --update-tiles hook and its report.
#include "apps/tinbase/edit_tiles.h"

#include <iostream>

namespace tinbase::cli {

std::function<Status(Store& store, int64_t tx)> EditTiles::Hook() {
  if (!wanted) return {};
  return UpdateTilesBeforeCommit(&updates);
}

void EditTiles::Print() const {
  if (!wanted) return;
  for (const auto& [surface, r] : updates)
    std::cout << "tiles of '" << surface.name << "': " << r.tiles_rewritten << " rewritten, "
              << r.tiles_deleted << " deleted" << (r.full_rebuild ? " (all rebuilt)" : "")
              << " with the edit\n";
}

}  // namespace tinbase::cli
