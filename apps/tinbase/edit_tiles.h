// `--update-tiles` of the edit commands (polygon add|update|remove, points add|remove): the tile
// pyramids brought up to date inside the edit's own transaction (db/tiles/tiles_with_edit.h), so
// the edit and its tiles commit together or not at all, and what was rewritten printed after.
#pragma once

#include <cstdint>
#include <functional>

#include "core/base/status.h"
#include "db/store.h"
#include "db/tiles/tiles_with_edit.h"

namespace tinbase::cli {

struct EditTiles {
  bool wanted = false;  // --update-tiles
  TileUpdates updates;  // filled by the hook

  // The hook for the edit's before_commit: empty unless wanted. REQUIRES: *this outlives it.
  std::function<Status(Store& store, int64_t tx)> Hook();

  // One line per updated surface on stdout, after the edit committed; nothing unless wanted.
  void Print() const;
};

}  // namespace tinbase::cli
