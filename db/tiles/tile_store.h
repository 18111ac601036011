// TileStore: the SQL of the tile tables (`tile_pyramids`, `tile_levels`, `tiles`;
// docs/format.md), one pyramid per surface.
//
// Tiles live in the store rather than as files, so a pyramid is written in one transaction with
// the state it shows, and an edit can replace the tiles it changed in the same way. Reads and
// writes as MeshTables: nothing here opens a transaction; writes REQUIRE a WriteTransaction.
// Borrows the connection; not thread-safe.
#pragma once

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "core/tiles/tiling_scheme.h"
#include "db/sql/connection.h"

namespace tinbase {

struct TilePyramidInfo {
  int64_t surface = 0;
  int max_zoom = 0;
  std::string extensions;  // as built: "octvertexnormals,watermask,metadata", or ""
  std::optional<std::string> water_tag;
  double min_height = 0;  // the quantisation range of every tile, metres
  double max_height = 0;
  // The tiles show every change up to it (0: none), and perhaps some after it
  // (db/change_log.h SettledThrough): an update reads the changes after it.
  int64_t tx = 0;
  // A vertex of the surface at min_height and one at max_height (store ids); nullopt for a
  // pyramid written before they were recorded.
  std::optional<int64_t> min_vertex;
  std::optional<int64_t> max_vertex;
};

class TileStore {
 public:
  explicit TileStore(Connection& db) : db_(db) {}

  // The surface's pyramid, nullopt when none was built.
  Result<std::optional<TilePyramidInfo>> Pyramid(int64_t surface);
  // Replaces the surface's pyramid row, deleting its old levels and tiles.
  Status ReplacePyramid(const TilePyramidInfo& info);
  // Deletes the surface's pyramid, levels and tiles.
  Status DeletePyramid(int64_t surface);
  Status PutLevel(int64_t surface, int level, double geometric_error);
  Status PutTile(int64_t surface, const TileKey& key, const std::vector<uint8_t>& data, int64_t tx);
  Status DeleteTile(int64_t surface, const TileKey& key);
  // Records that the pyramid now shows the state after transaction `tx`.
  Status SetPyramidTx(int64_t surface, int64_t tx);
  // Records the vertices at the ends of the pyramid's height range (TilePyramidInfo).
  Status SetHeightVertices(int64_t surface, int64_t min_vertex, int64_t max_vertex);
  // The tile's bytes and transaction; nullopt when the pyramid has no such tile.
  Result<std::optional<std::pair<std::vector<uint8_t>, int64_t>>> Tile(int64_t surface,
                                                                       const TileKey& key);
  // Every tile key of the surface's pyramid.
  Result<std::set<TileKey>> Keys(int64_t surface);
  // (level, geometric error) from the coarsest level.
  Result<std::vector<std::pair<int, double>>> Levels(int64_t surface);
  // The number of tiles and their bytes.
  Result<std::pair<int64_t, int64_t>> CountAndBytes(int64_t surface);

 private:
  Connection& db_;
};

// The newest transaction in the change log, 0 when it is empty.
Result<int64_t> LatestChange(Connection& db);

}  // namespace tinbase
