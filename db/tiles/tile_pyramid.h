// Tile pyramid: a surface's quantized-mesh tiles built into the store, and read back out as
// Cesium expects them (layer.json, a z/x/y.terrain tree). docs/tiles.md says what a client gets.
//
// A build reads the surface window by window (db/tiles/tile_window.h), turns each window into
// longitude/latitude (core/tiles/level_surfaces.h), cuts its finest tiles (core/tiles/
// tile_cutter.h) and merges them up on TBB's threads, writing tiles as they are made; the levels
// above the windows are merged from their children read back from the store. Memory is bounded
// by the window size, not the surface's. Everything is written in one write transaction: a
// failed build leaves the old pyramid as it was. An update reads only the window its changes
// meet. Thread-safety: as the Store.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "db/store.h"
#include "db/surface_store.h"
#include "db/tiles/tile_store.h"

namespace tinbase {

struct TileExtensions {
  bool normals = false;       // "octvertexnormals"
  bool water_mask = false;    // "watermask"
  bool metadata = false;      // "metadata"
  std::string Names() const;  // "octvertexnormals,watermask,metadata" (those set), or ""
};
// "octvertexnormals,metadata,watermask" in any order, or ""; InvalidArgument naming an unknown
// extension and listing the known ones.
Result<TileExtensions> ParseTileExtensions(const std::string& text);

struct TileBuildOptions {
  std::optional<int> max_zoom;  // default: the surface's natural zoom (NaturalMaxZoom)
  TileExtensions extensions;
  // The tag whose visible triangles are water in the water mask (e.g. a reservoir's feature tag).
  // REQUIRES with extensions.water_mask.
  std::optional<std::string> water_tag;
  // Told the fraction done as windows and levels are done; may be empty.
  std::function<void(double fraction)> progress;
  // About how many triangles one window of the build reads at a time (docs/tiles.md,
  // "Windows"): what bounds its memory. The tiles do not depend on it.
  int64_t window_triangles = int64_t{1} << 16;
};

struct TileLevelReport {
  int level = 0;
  double geometric_error = 0;  // the level's vertical error bound, metres
  int64_t tiles = 0;
  int64_t triangles = 0;
  int64_t bytes = 0;
};

struct TileBuildReport {
  TilePyramidInfo pyramid;
  std::vector<TileLevelReport> levels;  // coarsest first
};

// Builds the pyramid of `surface` from level 0 to the max zoom, replacing any pyramid it had.
// InvalidArgument for: a store without CRS or one with no transformation to EPSG:4326, a max
// zoom outside 0..24, a water mask without water tag or a water tag with no triangles; NotFound
// for an empty surface. Writes in its own transaction, or inside the caller's write transaction
// when one is open (db/tiles/tile_write_scope.h: the caller then rolls back on an error).
Result<TileBuildReport> BuildTilePyramid(Store& store, const SurfaceInfo& surface,
                                         const TileBuildOptions& options);

struct TileUpdateReport {
  int64_t since_tx = 0;         // the pyramid's transaction before the update
  int64_t tx = 0;               // and after
  int64_t changes = 0;          // changes of the surface read from the log
  bool full_rebuild = false;    // the height range changed: every tile was rebuilt
  int64_t tiles_meeting = 0;    // tiles, before or after, whose bounds meet the changed region
  int64_t tiles_rewritten = 0;  // of those, written again
  int64_t tiles_deleted = 0;    // of those, gone (now empty)
  // Where the time went (seconds): reading the window, heights and tiles the update needs;
  // cutting and merging the tiles; writing them.
  double read_seconds = 0;
  double make_seconds = 0;
  double write_seconds = 0;
};

// Brings the surface's pyramid up to date with the change log: every tile, at every level, whose
// closed bounds meet the region of a change since the pyramid's transaction is made again (or
// deleted when it came out empty); no other tile is touched, and the result equals a fresh build
// with the same options byte for byte (docs/tiles.md, "Updates"). When an edit moved the
// surface's height range, every tile's quantisation changes: then the whole pyramid is rebuilt.
// InvalidArgument "surface 's' has no tiles to update" when none was built. Transactions as
// BuildTilePyramid: inside an edit's write transaction, the tiles commit with the edit.
Result<TileUpdateReport> UpdateTilePyramid(Store& store, const SurfaceInfo& surface);

// UpdateTilePyramid for every surface that has a pyramid, in surface order: what an edit run with
// --update-tiles does after it commits. Returns each updated surface with its report.
Result<std::vector<std::pair<SurfaceInfo, TileUpdateReport>>> UpdateAllTilePyramids(Store& store);

// The tile `key` of the surface's pyramid made on demand from the stored surface alone (its
// window, down to the pyramid's finest level), with the pyramid's constants: the bytes the
// pyramid holds for it when it is up to date. Nothing is written. NotFound when the surface has
// no pyramid or the tile is empty; InvalidArgument for a key outside the pyramid's levels.
Result<std::vector<uint8_t>> MakeTile(Store& store, const SurfaceInfo& surface, const TileKey& key);

// Cesium's layer.json of the surface's pyramid: exact `available` rectangles per level, the
// extensions, and under "tinbase" the levels' error bounds and the pyramid's transaction.
// NotFound "surface 's' has no tiles (run tinbase tiles build)" when none was built.
Result<nlohmann::json> LayerJson(Store& store, const SurfaceInfo& surface);

// Writes DIR/layer.json and DIR/z/x/y.terrain for every tile (gzipped when `gzip`, as static
// hosts serve them with Content-Encoding: gzip). The tree is written beside DIR and renamed onto
// it when complete. IOError when DIR exists and is not empty, or cannot be written; NotFound as
// LayerJson.
Status ExportTiles(Store& store, const SurfaceInfo& surface, const std::string& dir, bool gzip);

}  // namespace tinbase
