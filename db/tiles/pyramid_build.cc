// Tile pyramid build: BuildTilePyramid of tile_pyramid.h, in bounded memory.
//
// One scan of the vertices gives the height range, the geographic box and the natural max zoom.
// The windows are then the tiles of the coarsest level whose tiles hold, at the surface's mean
// density, about TileBuildOptions::window_triangles triangles. Each window's finest tiles are cut
// from its part of the surface (db/tiles/tile_window.h), merged up to the window's level and
// written; the window is then dropped. The levels above are merged one at a time from their
// children read back from the store. A finest tile depends only on the surface around it and a
// coarser one only on its children, so the tiles do not depend on the window size.
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "core/tiles/level_surfaces.h"
#include "db/change_log.h"
#include "db/mesh/mesh_tables.h"
#include "db/tiles/pyramid_levels.h"
#include "db/tiles/tile_pyramid.h"
#include "db/tiles/tile_window.h"
#include "db/tiles/tile_write_scope.h"

namespace tinbase {

namespace {

Status CheckOptions(const TileBuildOptions& options) {
  if (options.max_zoom && (*options.max_zoom < 0 || *options.max_zoom > kMaxTileLevel))
    return Status::InvalidArgument("--max-zoom " + std::to_string(*options.max_zoom) +
                                   " is outside 0.." + std::to_string(kMaxTileLevel));
  if (options.extensions.water_mask && !options.water_tag)
    return Status::InvalidArgument(
        "the watermask extension needs --water-tag (the tag of the features that are water)");
  if (options.water_tag && !options.extensions.water_mask)
    return Status::InvalidArgument("--water-tag needs the watermask extension");
  return Status::Ok();
}

// The coarsest level whose tiles hold at most `budget` of the surface's triangles at its mean
// density, no finer than the max zoom.
int WindowLevel(const SurfaceSummary& s, int64_t triangles, int max_zoom, int64_t budget) {
  const double area = std::max((s.east - s.west) * (s.north - s.south), 1e-18);
  for (int level = 0; level < max_zoom; ++level) {
    const double share = std::min(1.0, TileDegrees(level) * TileDegrees(level) / area);
    if (static_cast<double>(triangles) * share <= static_cast<double>(std::max<int64_t>(budget, 1)))
      return level;
  }
  return max_zoom;
}

// Writes tiles and counts them in the report's levels; keeps every written key.
class TileWriter {
 public:
  TileWriter(TileStore& tiles, const PyramidInputs& in, bool metadata, TileBuildReport* report)
      : tiles_(tiles), in_(in), metadata_(metadata), report_(report) {
    for (int level = 0; level <= in.pyramid.max_zoom; ++level)
      report_->levels.push_back({level, LevelError(in, level), 0, 0, 0});
  }

  // Writes the non-empty tiles of `made`; the metadata of a tile comes from `keys`, which must
  // hold every tile below it (within kMetadataAvailability levels).
  Status Write(std::map<TileKey, std::optional<QuantizedMesh>>& made,
               const std::set<TileKey>& keys) {
    for (auto& [key, mesh] : made) {
      if (!mesh) continue;
      if (metadata_ && key.level % kMetadataAvailability == 0)
        mesh->metadata = MetadataOf(keys, key);
      TB_ASSIGN_OR_RETURN(const std::vector<uint8_t> bytes, EncodeQuantizedMesh(*mesh));
      TB_RETURN_IF_ERROR(tiles_.PutTile(in_.pyramid.surface, key, bytes, in_.pyramid.tx));
      TileLevelReport& line = report_->levels[key.level];
      ++line.tiles;
      line.triangles += static_cast<int64_t>(mesh->triangles.size() / 3);
      line.bytes += static_cast<int64_t>(bytes.size());
      written_.insert(key);
    }
    return Status::Ok();
  }

  const std::set<TileKey>& written() const { return written_; }

 private:
  TileStore& tiles_;
  const PyramidInputs& in_;
  bool metadata_;
  TileBuildReport* report_;
  std::set<TileKey> written_;
};

std::set<TileKey> KeysOf(const std::map<TileKey, std::optional<QuantizedMesh>>& made) {
  std::set<TileKey> keys;
  for (const auto& [key, mesh] : made)
    if (mesh) keys.insert(key);
  return keys;
}

// The tiles of the window `w` (a tile), from the finest level up to w's; every level empty when
// the window holds no triangle. Sets in.water_tag to the window's index of the water tag.
Result<MadeLevels> MakeWindow(Store& store, const SurfaceInfo& surface, const Crs& crs,
                              const TileBuildOptions& options, PyramidInputs& in,
                              const TileKey& w) {
  const int max = in.pyramid.max_zoom;
  TB_ASSIGN_OR_RETURN(TileWindow window, ReadTileWindow(store, surface, crs, RectOf(w), max));
  in.water_tag = kNoTag;
  if (window.tin.triangles.empty()) return MadeLevels(max + 1);
  in.water_tag = TagIndex(window.tin, options.water_tag);
  TB_ASSIGN_OR_RETURN(in.finest, GeographicSurface(window.tin, crs, options.extensions.normals,
                                                   in.pyramid.min_height, in.pyramid.max_height));
  window = TileWindow();
  const int shift = max - w.level;
  const auto inside = [&](const TileKey& key) {
    return (key.x >> shift) == w.x && (key.y >> shift) == w.y;
  };
  TileBuildOptions quiet = options;
  quiet.progress = nullptr;
  MadeLevels made = MakeLevels(in, quiet, inside, {}, nullptr, w.level);
  in.finest = GeoSurface();
  return made;
}

// The window `w`'s tiles written. Returns whether the window holds the water tag.
Result<bool> BuildWindow(Store& store, const SurfaceInfo& surface, const Crs& crs,
                         const TileBuildOptions& options, PyramidInputs& in, const TileKey& w,
                         TileWriter& writer) {
  const int max = in.pyramid.max_zoom;
  TB_ASSIGN_OR_RETURN(MadeLevels made, MakeWindow(store, surface, crs, options, in, w));
  std::set<TileKey> keys;
  for (int level = w.level; level <= max; ++level) keys.merge(KeysOf(made[level]));
  for (int level = max; level >= w.level; --level)
    TB_RETURN_IF_ERROR(writer.Write(made[level], keys));
  return in.water_tag != kNoTag;
}

}  // namespace

Result<TileBuildReport> BuildTilePyramid(Store& store, const SurfaceInfo& surface,
                                         const TileBuildOptions& options) {
  TB_RETURN_IF_ERROR(CheckOptions(options));
  TB_ASSIGN_OR_RETURN(const std::optional<Crs> crs, store.GetCrs());
  if (!crs)
    return Status::InvalidArgument(
        "the store has no CRS: tiles need one that transforms to "
        "EPSG:4326 (set it with tinbase init --crs)");
  TB_ASSIGN_OR_RETURN(TileWriteScope tx, TileWriteScope::Begin(store));
  TB_ASSIGN_OR_RETURN(const int64_t triangles, MeshTables(store.db(), surface).CountTriangles());
  if (triangles == 0)
    return Status::NotFound("surface '" + surface.name + "' has no triangles to tile");
  TB_ASSIGN_OR_RETURN(const SurfaceSummary summary,
                      Summarise(store, surface, *crs, /*geographic=*/true));
  PyramidInputs in;
  in.pyramid.surface = surface.id;
  in.pyramid.extensions = options.extensions.Names();
  in.pyramid.water_tag = options.water_tag;
  in.pyramid.min_height = summary.extremes.min;
  in.pyramid.max_height = summary.extremes.max;
  in.pyramid.min_vertex = summary.extremes.min_vertex;
  in.pyramid.max_vertex = summary.extremes.max_vertex;
  TB_ASSIGN_OR_RETURN(in.pyramid.tx, SettledLastTransaction(store));
  in.pyramid.max_zoom = options.max_zoom.value_or(
      NaturalMaxZoom(summary.west, summary.south, summary.east, summary.north, summary.vertices));
  in.base_error = surface.tolerance.value_or(1.0);
  const int max = in.pyramid.max_zoom;

  TileStore tiles(store.db());
  TB_RETURN_IF_ERROR(tiles.ReplacePyramid(in.pyramid));
  for (int level = 0; level <= max; ++level)
    TB_RETURN_IF_ERROR(tiles.PutLevel(surface.id, level, LevelError(in, level)));
  TileBuildReport report;
  report.pyramid = in.pyramid;
  TileWriter writer(tiles, in, options.extensions.metadata, &report);

  // Snapping moves a vertex by less than a quantisation step of the finest level.
  const double step = TileDegrees(max) / kQuantizedMax;
  const int window_level = WindowLevel(summary, triangles, max, options.window_triangles);
  const TileRange windows = TilesMeeting(window_level, summary.west - step, summary.south - step,
                                         summary.east + step, summary.north + step);
  bool water_seen = false;
  int64_t done = 0;
  for (int64_t y = windows.y0; y <= windows.y1; ++y)
    for (int64_t x = windows.x0; x <= windows.x1; ++x) {
      TB_ASSIGN_OR_RETURN(const bool water, BuildWindow(store, surface, *crs, options, in,
                                                        {window_level, x, y}, writer));
      water_seen = water_seen || water;
      if (options.progress)
        options.progress(0.9 * static_cast<double>(++done) / static_cast<double>(windows.count()));
    }
  if (options.water_tag && !water_seen)
    return Status::InvalidArgument("no triangle of surface '" + surface.name + "' has tag '" +
                                   *options.water_tag + "' (the --water-tag)");

  for (int level = window_level - 1; level >= 0; --level) {
    std::set<TileKey> parents;
    for (const TileKey& k : writer.written())
      if (k.level == level + 1) parents.insert({level, k.x / 2, k.y / 2});
    StoredTiles stored(tiles, surface.id);
    auto made =
        MergeLevel(in, options, parents, [&](const TileKey& key) { return stored.Get(key); });
    TB_RETURN_IF_ERROR(stored.error());
    std::set<TileKey> keys = writer.written();
    keys.merge(KeysOf(made));
    TB_RETURN_IF_ERROR(writer.Write(made, keys));
  }
  TB_RETURN_IF_ERROR(tx.Commit());
  if (options.progress) options.progress(1.0);
  return report;
}

Result<std::vector<uint8_t>> MakeTile(Store& store, const SurfaceInfo& surface,
                                      const TileKey& key) {
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  TileStore tiles(store.db());
  TB_ASSIGN_OR_RETURN(const std::optional<TilePyramidInfo> pyramid, tiles.Pyramid(surface.id));
  if (!pyramid)
    return Status::NotFound("surface '" + surface.name +
                            "' has no tiles (run tinbase tiles build first)");
  if (key.level < 0 || key.level > pyramid->max_zoom || key.x < 0 ||
      key.x >= TilesAcross(key.level) || key.y < 0 || key.y >= TilesDown(key.level))
    return Status::InvalidArgument("tile " + key.ToString() + " is outside the pyramid (levels 0-" +
                                   std::to_string(pyramid->max_zoom) + ")");
  TB_ASSIGN_OR_RETURN(const std::optional<Crs> crs, store.GetCrs());
  if (!crs) return Status::InvalidArgument("the store has no CRS");
  TileBuildOptions options;
  options.max_zoom = pyramid->max_zoom;
  TB_ASSIGN_OR_RETURN(options.extensions, ParseTileExtensions(pyramid->extensions));
  options.water_tag = pyramid->water_tag;
  PyramidInputs in;
  in.pyramid = *pyramid;
  in.base_error = surface.tolerance.value_or(1.0);
  TB_ASSIGN_OR_RETURN(MadeLevels made, MakeWindow(store, surface, *crs, options, in, key));
  auto it = made[key.level].find(key);
  if (it == made[key.level].end() || !it->second)
    return Status::NotFound("tile " + key.ToString() + " of surface '" + surface.name +
                            "' is empty");
  QuantizedMesh& mesh = *it->second;
  if (options.extensions.metadata && key.level % kMetadataAvailability == 0) {
    std::set<TileKey> keys;
    for (int level = key.level; level <= pyramid->max_zoom; ++level)
      keys.merge(KeysOf(made[level]));
    mesh.metadata = MetadataOf(keys, key);
  }
  return EncodeQuantizedMesh(mesh);
}

}  // namespace tinbase
