// The tile pyramids brought up to date inside an edit's own write transaction: the hook an edit
// runs just before it commits (PolygonAddOptions::before_commit, db/polygon_editor.h), so the
// edit and the tiles it made stale commit together or not at all. `tinbase serve`'s edit routes
// and the CLI's `--update-tiles` both use it.
// Thread-safety: as the Store.
#pragma once

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "db/store.h"
#include "db/surface_store.h"
#include "db/tiles/tile_pyramid.h"

namespace tinbase {

// Each updated surface with its report, in surface order (UpdateAllTilePyramids); over several
// edits (`--each`), each surface once with the tiles of all of them added up.
using TileUpdates = std::vector<std::pair<SurfaceInfo, TileUpdateReport>>;

// A before-commit hook that runs UpdateAllTilePyramids in the edit's transaction and adds what it
// did to `*updates`. Its error is the edit's, with the context "updating the tiles of the edit",
// and rolls the edit back (what it added for that edit stays in `*updates`: the caller reports
// `*updates` only after a commit).
// REQUIRES: `updates` outlives the hook.
std::function<Status(Store& store, int64_t tx)> UpdateTilesBeforeCommit(TileUpdates* updates);

// The tiles rewritten plus deleted over all of `updates`.
int64_t TilesTouched(const TileUpdates& updates);

}  // namespace tinbase
