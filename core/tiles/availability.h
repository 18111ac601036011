// Tile availability: the set of tiles a pyramid holds, as the rectangles of tile coordinates
// that Cesium's layer.json `available` array and the metadata extension list, per level.
//
// The rectangles are exact: together they cover every tile that exists and no other. Pure
// functions; plain data.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "core/tiles/tiling_scheme.h"

namespace tinbase {

struct TileRectangle {
  int64_t start_x = 0, start_y = 0, end_x = 0, end_y = 0;  // inclusive
  friend bool operator==(const TileRectangle&, const TileRectangle&) = default;
};

// The tiles of one level as rectangles: runs of consecutive x per row, then runs that repeat on
// consecutive rows merged. REQUIRES: every key has level `level`.
std::vector<TileRectangle> RectanglesOf(const std::set<TileKey>& tiles, int level);

// Cesium's form: [[{"startX":..,"startY":..,"endX":..,"endY":..}, ...], ...], one array per level
// from `first_level` up (levels with no tiles get an empty array).
nlohmann::json AvailableJson(const std::set<TileKey>& tiles, int first_level, int last_level);

// The tiles under `root` (its own level excluded) down to `depth` levels below it.
std::set<TileKey> SubtreeOf(const std::set<TileKey>& tiles, const TileKey& root, int depth);

}  // namespace tinbase
