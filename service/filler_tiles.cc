// Filler tiles above a pyramid's coarsest stored level.
#include "service/filler_tiles.h"

#include <cmath>
#include <map>
#include <mutex>
#include <set>
#include <utility>
#include <vector>

#include "core/tiles/availability.h"
#include "core/tiles/tile_bounds.h"
#include "core/tiles/tile_mesh_builder.h"
#include "db/tiles/tile_store.h"

namespace tinbase::service {

namespace {

// Cells across a filler tile: a level-0 cell then spans 11.25 degrees, as in the flat tiles
// Cesium makes for its own ellipsoid terrain.
constexpr int kFillerCells = 16;

// Levels a tile's metadata covers below it: layer.json's metadataAvailability (db/tiles).
constexpr int kMetadataLevels = 10;

Ecef EllipsoidNormal(double lon, double lat) {
  const double l = lon * M_PI / 180, p = lat * M_PI / 180;
  return {std::cos(p) * std::cos(l), std::cos(p) * std::sin(l), std::sin(p)};
}

}  // namespace

Result<int> CoarsestStoredLevel(Store& store, const std::string& store_path,
                                const TilePyramidInfo& pyramid) {
  // One entry per store and surface, for the pyramid state it was read at: an edit's new state
  // replaces it, so the cache stays as small as the set of surfaces served.
  struct Entry {
    int64_t tx = -1;
    int max_zoom = -1;
    int coarsest = 0;
  };
  static std::mutex mutex;
  static std::map<std::pair<std::string, int64_t>, Entry> cache;
  const std::pair<std::string, int64_t> key{store_path, pyramid.surface};
  {
    std::lock_guard<std::mutex> lock(mutex);
    const auto it = cache.find(key);
    if (it != cache.end() && it->second.tx == pyramid.tx && it->second.max_zoom == pyramid.max_zoom)
      return it->second.coarsest;
  }
  TB_ASSIGN_OR_RETURN(const std::set<TileKey> keys, TileStore(store.db()).Keys(pyramid.surface));
  const int coarsest = keys.empty() ? pyramid.max_zoom + 1 : keys.begin()->level;
  std::lock_guard<std::mutex> lock(mutex);
  cache[key] = Entry{pyramid.tx, pyramid.max_zoom, coarsest};
  return coarsest;
}

bool IsFillerLevel(int level, int coarsest) { return level == 0 || level < coarsest; }

Result<QuantizedMesh> FillerTile(const TileKey& key, const TilePyramidInfo& pyramid, bool normals,
                                 const std::optional<std::string>& metadata) {
  const TileRect rect = RectOf(key);
  TileMeshBuilder builder(rect, pyramid.min_height, pyramid.max_height, normals);
  const double h = pyramid.min_height;
  const auto point = [&](int i, int j) {
    // Grid lines from the rectangle's own edges at the ends, so the edge coordinates are exact.
    const double lon =
        i == kFillerCells ? rect.east : rect.west + (rect.east - rect.west) * i / kFillerCells;
    const double lat =
        j == kFillerCells ? rect.north : rect.south + (rect.north - rect.south) * j / kFillerCells;
    return TilePoint{lon, lat, h, EllipsoidNormal(lon, lat)};
  };
  for (int j = 0; j < kFillerCells; ++j)
    for (int i = 0; i < kFillerCells; ++i)
      builder.AddPolygon({point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1)});
  std::optional<QuantizedMesh> mesh = builder.Finish();
  if (!mesh) return Status::Corruption("filler tile " + key.ToString() + " came out empty");
  mesh->metadata = metadata;
  return std::move(*mesh);
}

std::string FillerMetadata(const TileKey& root, const std::set<TileKey>& stored, int coarsest) {
  nlohmann::json available =
      AvailableJson(SubtreeOf(stored, root, kMetadataLevels), 1, kMetadataLevels);
  for (int level = 1; level <= kMetadataLevels && level < coarsest; ++level) {
    const int64_t across = int64_t{1} << level;  // a root's tiles per side, `level` below it
    available[level - 1] = nlohmann::json::array({{{"startX", root.x * across},
                                                   {"startY", 0},
                                                   {"endX", (root.x + 1) * across - 1},
                                                   {"endY", across - 1}}});
  }
  // Trailing levels without tiles say nothing; Cesium reads the array by level offset.
  while (!available.empty() && available.back().empty()) available.erase(available.size() - 1);
  return nlohmann::json{{"available", available}}.dump();
}

void AddFillerAvailability(nlohmann::json& layer, int coarsest) {
  nlohmann::json& available = layer["available"];
  if (!available.is_array()) return;
  for (int level = 0; level < static_cast<int>(available.size()); ++level) {
    if (!IsFillerLevel(level, coarsest)) continue;
    available[level] = nlohmann::json::array({{{"startX", 0},
                                               {"startY", 0},
                                               {"endX", TilesAcross(level) - 1},
                                               {"endY", TilesDown(level) - 1}}});
  }
}

}  // namespace tinbase::service
