// Pyramid levels: what a tile pyramid's build and its update share (db/tiles/tile_pyramid.h):
// the pyramid's constants, the finest level cut from a surface (whole, or a window of it), each
// coarser level merged from the level below, and the metadata extension's availability.
// Internal to db/tiles. Thread-safety: pure functions over their arguments (the cutting and
// merging run on TBB's threads).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/geometry/crs.h"
#include "core/tiles/quantized_mesh.h"
#include "core/tiles/tile_cutter.h"
#include "db/store.h"
#include "db/surface_store.h"
#include "db/tiles/tile_pyramid.h"
#include "db/tiles/tile_store.h"

namespace tinbase {

// Tiles at levels that are multiples of this carry the availability of the levels below them
// in the metadata extension, as Cesium's own terrain does.
inline constexpr int kMetadataAvailability = 10;

// The pyramid's constants, and the surface (whole, or the window an update needs) in
// longitude/latitude.
struct PyramidInputs {
  TilePyramidInfo pyramid;
  GeoSurface finest;
  int32_t water_tag = kNoTag;  // an index into finest.tin.tags
  double base_error = 1;
};

// The lowest and highest height of a surface's vertices in metres, and a vertex (store id) at
// each; a flat surface gets max = min + 1, so the quantisation range is never empty.
struct HeightExtremes {
  double min = 0;
  double max = 0;
  int64_t min_vertex = 0;
  int64_t max_vertex = 0;
};
HeightExtremes ExtremesOf(const LoadedSurface& surface, const Crs& crs);
// [min, max] as a pyramid quantises against it (max > min).
std::pair<double, double> QuantisationRange(double min, double max);

// What a build needs to know of a surface before it reads it window by window: the height
// extremes of its vertices, their count, and (when asked) their geographic box in degrees.
struct SurfaceSummary {
  HeightExtremes extremes;
  int64_t vertices = 0;
  double west = 0, south = 0, east = 0, north = 0;
};
// One scan of the surface's vertices, a bounded number in memory at a time. NotFound when it
// has none; InvalidArgument when `geographic` and the CRS does not transform to EPSG:4326.
Result<SurfaceSummary> Summarise(Store& store, const SurfaceInfo& surface, const Crs& crs,
                                 bool geographic);

// The decoded tiles of a pyramid in the store, read once each and kept until destroyed: the
// children a merge reads back. The first read error is kept in error().
class StoredTiles {
 public:
  StoredTiles(TileStore& tiles, int64_t surface) : tiles_(tiles), surface_(surface) {}

  const QuantizedMesh* Get(const TileKey& key);
  const Status& error() const { return error_; }

 private:
  std::optional<QuantizedMesh> Read(const TileKey& key);

  TileStore& tiles_;
  int64_t surface_;
  std::map<TileKey, std::optional<QuantizedMesh>> read_;
  Status error_;
};

// The index of `tag` in `tin`'s tags, kNoTag when absent or not asked for.
int32_t TagIndex(const Tin& tin, const std::optional<std::string>& tag);

// The vertical error bound of `level`: 0 for the finest; one level up, the surface's tolerance;
// doubling per level up.
double LevelError(const PyramidInputs& in, int level);

using MadeLevels = std::vector<std::map<TileKey, std::optional<QuantizedMesh>>>;

// The tiles that `wanted` accepts at the finest level and those of `also` (at any level), and
// their ancestors up to level `top`, each coarser tile from its children: those made here, else
// from `stored` (tiles already in the store). Empty tiles are nullopt. Indexed by level (those
// above `top` empty).
MadeLevels MakeLevels(const PyramidInputs& in, const TileBuildOptions& options,
                      const std::function<bool(const TileKey&)>& wanted,
                      const std::set<TileKey>& also,
                      const std::function<const QuantizedMesh*(const TileKey&)>& stored, int top);

// The tiles of `level` whose keys are `parents`, each merged from its four children, which
// `child` finds (null when the child does not exist); nullopt for an empty one.
std::map<TileKey, std::optional<QuantizedMesh>> MergeLevel(
    const PyramidInputs& in, const TileBuildOptions& options, const std::set<TileKey>& parents,
    const std::function<const QuantizedMesh*(const TileKey&)>& child);

struct LevelTiles {
  int level = 0;
  double geometric_error = 0;
  std::map<TileKey, QuantizedMesh> meshes;
};

// The made tiles as LevelTiles (empty ones left out), coarsest first.
std::vector<LevelTiles> NonEmpty(MadeLevels made, const PyramidInputs& in);

// The metadata extension's JSON of tile `key`: the availability of the levels below it in
// `all`, the pyramid's keys.
std::string MetadataOf(const std::set<TileKey>& all, const TileKey& key);

}  // namespace tinbase
