// Tile pyramid: see tile_pyramid.h.
#include "db/tiles/tile_pyramid.h"

#include <tbb/parallel_for.h>
#include <unistd.h>
#include <zlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>

#include "core/geometry/reproject.h"
#include "core/tiles/availability.h"
#include "core/tiles/coarse_tile.h"
#include "core/tiles/level_surfaces.h"
#include "core/tiles/tile_cutter.h"
#include "db/change_log.h"

namespace tinbase {

namespace {

// Tiles at levels that are multiples of this carry the availability of the levels below them
// in the metadata extension, as Cesium's own terrain does.
constexpr int kMetadataAvailability = 10;

struct LevelTiles {
  int level = 0;
  double geometric_error = 0;
  std::map<TileKey, QuantizedMesh> meshes;
};

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

int32_t TagIndex(const Tin& tin, const std::optional<std::string>& tag) {
  if (!tag) return kNoTag;
  for (size_t i = 0; i < tin.tags.size(); ++i)
    if (tin.tags[i] == *tag) return static_cast<int32_t>(i);
  return kNoTag;
}

// The finest level's tiles that `wanted` accepts, and those of `also` at this level, each the
// surface clipped to the tile, with its water mask. nullopt for a tile that came out empty.
std::map<TileKey, std::optional<QuantizedMesh>> CutFinest(
    const GeoSurface& finest, int level, int32_t water_tag, bool water_mask,
    const std::function<bool(const TileKey&)>& wanted, const std::set<TileKey>& also) {
  const TileCutter cutter(finest, level);
  std::set<TileKey> wanted_keys;
  for (const TileKey& key : cutter.Tiles())
    if (wanted(key)) wanted_keys.insert(key);
  for (const TileKey& key : also)
    if (key.level == level) wanted_keys.insert(key);
  const std::vector<TileKey> keys(wanted_keys.begin(), wanted_keys.end());
  std::vector<std::optional<QuantizedMesh>> made(keys.size());
  tbb::parallel_for(size_t{0}, keys.size(), [&](size_t i) {
    made[i] = cutter.Cut(keys[i]);
    if (made[i] && water_mask) made[i]->water_mask = cutter.WaterMask(keys[i], water_tag);
  });
  std::map<TileKey, std::optional<QuantizedMesh>> out;
  for (size_t i = 0; i < keys.size(); ++i) out.emplace(keys[i], std::move(made[i]));
  return out;
}

// The tiles of one coarser level whose keys are `parents`, each from its four children, which
// `child` finds (null when the child does not exist).
std::map<TileKey, std::optional<QuantizedMesh>> MergeLevel(
    const std::set<TileKey>& parents, const CoarseTileOptions& coarse, bool water_mask,
    const std::function<const QuantizedMesh*(const TileKey&)>& child) {
  const std::vector<TileKey> keys(parents.begin(), parents.end());
  std::vector<std::array<const QuantizedMesh*, 4>> children(keys.size());
  for (size_t i = 0; i < keys.size(); ++i)
    for (int c = 0; c < 4; ++c)
      children[i][c] = child({keys[i].level + 1, 2 * keys[i].x + c % 2, 2 * keys[i].y + c / 2});
  std::vector<std::optional<QuantizedMesh>> made(keys.size());
  tbb::parallel_for(size_t{0}, keys.size(), [&](size_t i) {
    made[i] = MergeChildren(children[i], keys[i], coarse);
    if (made[i] && water_mask) made[i]->water_mask = MergeWaterMasks(children[i]);
  });
  std::map<TileKey, std::optional<QuantizedMesh>> out;
  for (size_t i = 0; i < keys.size(); ++i) out.emplace(keys[i], std::move(made[i]));
  return out;
}

std::set<TileKey> ParentsOf(const std::set<TileKey>& keys) {
  std::set<TileKey> parents;
  for (const TileKey& k : keys) parents.insert({k.level - 1, k.x / 2, k.y / 2});
  return parents;
}

// Everything a build or an update reads from the store and computes once.
struct PyramidInputs {
  TilePyramidInfo pyramid;
  GeoSurface finest;
  int32_t water_tag = kNoTag;
  double base_error = 1;
};

// The vertical error bound of `level`: 0 for the finest; one level up, the surface's tolerance;
// doubling per level up.
double LevelError(const PyramidInputs& in, int level) {
  if (level == in.pyramid.max_zoom) return 0;
  return std::ldexp(in.base_error, in.pyramid.max_zoom - level - 1);
}

Result<PyramidInputs> ReadInputs(Store& store, const SurfaceInfo& surface,
                                 const TileBuildOptions& options) {
  TB_ASSIGN_OR_RETURN(std::optional<Crs> crs, store.GetCrs());
  if (!crs)
    return Status::InvalidArgument(
        "the store has no CRS: tiles need one that transforms to "
        "EPSG:4326 (set it with tinbase init --crs)");
  LoadedSurface loaded;
  PyramidInputs in;
  {
    TB_ASSIGN_OR_RETURN(auto snapshot, ReadSnapshot::Begin(store));
    TB_ASSIGN_OR_RETURN(loaded, SurfaceStore(store).Load(surface));
    TB_ASSIGN_OR_RETURN(in.pyramid.tx, LatestChange(store.db()));
  }
  if (loaded.tin.triangles.empty())
    return Status::NotFound("surface '" + surface.name + "' has no triangles to tile");
  in.water_tag = TagIndex(loaded.tin, options.water_tag);
  if (options.water_tag && in.water_tag == kNoTag)
    return Status::InvalidArgument("no triangle of surface '" + surface.name + "' has tag '" +
                                   *options.water_tag + "' (the --water-tag)");
  in.pyramid.surface = surface.id;
  in.pyramid.extensions = options.extensions.Names();
  in.pyramid.water_tag = options.water_tag;
  std::tie(in.pyramid.min_height, in.pyramid.max_height) = HeightRange(loaded.tin, *crs);
  if (!(in.pyramid.max_height > in.pyramid.min_height))
    in.pyramid.max_height = in.pyramid.min_height + 1;
  TB_ASSIGN_OR_RETURN(in.finest, GeographicSurface(loaded.tin, *crs, options.extensions.normals,
                                                   in.pyramid.min_height, in.pyramid.max_height));
  in.pyramid.max_zoom = options.max_zoom.value_or(NaturalMaxZoom(in.finest));
  in.base_error = surface.tolerance.value_or(1.0);
  return in;
}

CoarseTileOptions CoarseOptions(const PyramidInputs& in, int level) {
  CoarseTileOptions coarse;
  coarse.error = LevelError(in, level);
  coarse.min_height = in.pyramid.min_height;
  coarse.max_height = in.pyramid.max_height;
  return coarse;
}

// The tiles that `wanted` accepts at the finest level and those of `also` (at any level), and
// their ancestors, each coarser tile from its children: those made here, else from `stored` (an
// update's unchanged tiles). Empty tiles are nullopt.
std::vector<std::map<TileKey, std::optional<QuantizedMesh>>> MakeLevels(
    const PyramidInputs& in, const TileBuildOptions& options,
    const std::function<bool(const TileKey&)>& wanted, const std::set<TileKey>& also,
    const std::function<const QuantizedMesh*(const TileKey&)>& stored) {
  const int max = in.pyramid.max_zoom;
  std::vector<std::map<TileKey, std::optional<QuantizedMesh>>> levels(max + 1);
  levels[max] =
      CutFinest(in.finest, max, in.water_tag, options.extensions.water_mask, wanted, also);
  // The finest level is most of the work; the write counts as one more level.
  const auto report = [&](int done) {
    if (options.progress) options.progress(0.5 * done / (max + 2.0) + (done > 0 ? 0.4 : 0.0));
  };
  report(1);
  for (int level = max - 1; level >= 0; --level) {
    const auto& below = levels[level + 1];
    std::set<TileKey> keys;
    for (const auto& [key, mesh] : below) keys.insert(key);
    std::set<TileKey> parents = ParentsOf(keys);
    for (const TileKey& key : also)
      if (key.level == level) parents.insert(key);
    const auto child = [&](const TileKey& key) -> const QuantizedMesh* {
      if (auto it = below.find(key); it != below.end()) return it->second ? &*it->second : nullptr;
      return stored ? stored(key) : nullptr;
    };
    levels[level] =
        MergeLevel(parents, CoarseOptions(in, level), options.extensions.water_mask, child);
  }
  return levels;
}

// The made tiles as LevelTiles (empty ones left out), coarsest first.
std::vector<LevelTiles> NonEmpty(std::vector<std::map<TileKey, std::optional<QuantizedMesh>>> made,
                                 const PyramidInputs& in) {
  std::vector<LevelTiles> out;
  for (int level = 0; level < static_cast<int>(made.size()); ++level) {
    LevelTiles tiles{level, LevelError(in, level), {}};
    for (auto& [key, mesh] : made[level])
      if (mesh) tiles.meshes.emplace(key, std::move(*mesh));
    out.push_back(std::move(tiles));
  }
  return out;
}

std::string MetadataOf(const std::set<TileKey>& all, const TileKey& key) {
  const std::set<TileKey> below = SubtreeOf(all, key, kMetadataAvailability);
  nlohmann::json available = AvailableJson(below, key.level + 1, key.level + kMetadataAvailability);
  // Trailing levels without tiles say nothing; Cesium reads the array by level offset.
  while (!available.empty() && available.back().empty()) available.erase(available.size() - 1);
  return nlohmann::json{{"available", available}}.dump();
}

Status WritePyramid(Store& store, const TilePyramidInfo& pyramid, std::vector<LevelTiles>& levels,
                    bool metadata, TileBuildReport* report) {
  std::set<TileKey> all;
  for (const LevelTiles& level : levels)
    for (const auto& [key, mesh] : level.meshes) all.insert(key);
  TB_ASSIGN_OR_RETURN(auto tx, store.BeginWrite());
  TileStore tiles(store.db());
  TB_RETURN_IF_ERROR(tiles.ReplacePyramid(pyramid));
  for (LevelTiles& level : levels) {
    TB_RETURN_IF_ERROR(tiles.PutLevel(pyramid.surface, level.level, level.geometric_error));
    TileLevelReport line{level.level, level.geometric_error, 0, 0, 0};
    for (auto& [key, mesh] : level.meshes) {
      if (metadata && key.level % kMetadataAvailability == 0) mesh.metadata = MetadataOf(all, key);
      TB_ASSIGN_OR_RETURN(const std::vector<uint8_t> bytes, EncodeQuantizedMesh(mesh));
      TB_RETURN_IF_ERROR(tiles.PutTile(pyramid.surface, key, bytes, pyramid.tx));
      ++line.tiles;
      line.triangles += static_cast<int64_t>(mesh.triangles.size() / 3);
      line.bytes += static_cast<int64_t>(bytes.size());
    }
    report->levels.push_back(line);
  }
  return tx->Commit();
}

Result<std::vector<uint8_t>> Gzip(const std::vector<uint8_t>& in) {
  z_stream z{};
  constexpr int kGzipWindow = 15 + 16;  // 16: a gzip header and trailer instead of zlib's
  if (deflateInit2(&z, Z_BEST_COMPRESSION, Z_DEFLATED, kGzipWindow, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    return Status::IOError("zlib: deflateInit2 failed");
  std::vector<uint8_t> out(deflateBound(&z, in.size()) + 32);
  z.next_in = const_cast<Bytef*>(in.data());
  z.avail_in = static_cast<uInt>(in.size());
  z.next_out = out.data();
  z.avail_out = static_cast<uInt>(out.size());
  const int rc = deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  if (rc != Z_STREAM_END) return Status::IOError("zlib: deflate did not finish");
  return out;
}

Status WriteFile(const std::filesystem::path& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) return Status::IOError("cannot write '" + path.string() + "'");
  return Status::Ok();
}

}  // namespace

std::string TileExtensions::Names() const {
  std::string out;
  const auto add = [&out](const char* name) {
    if (!out.empty()) out += ',';
    out.append(name);
  };
  if (normals) add("octvertexnormals");
  if (water_mask) add("watermask");
  if (metadata) add("metadata");
  return out;
}

Result<TileExtensions> ParseTileExtensions(const std::string& text) {
  TileExtensions out;
  size_t start = 0;
  while (start <= text.size() && !text.empty()) {
    const size_t comma = text.find(',', start);
    const std::string name =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (name == "octvertexnormals") {
      out.normals = true;
    } else if (name == "watermask") {
      out.water_mask = true;
    } else if (name == "metadata") {
      out.metadata = true;
    } else {
      return Status::InvalidArgument("unknown tile extension '" + name +
                                     "' (expected octvertexnormals, watermask or metadata)");
    }
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

Result<TileBuildReport> BuildTilePyramid(Store& store, const SurfaceInfo& surface,
                                         const TileBuildOptions& options) {
  TB_RETURN_IF_ERROR(CheckOptions(options));
  TB_ASSIGN_OR_RETURN(const PyramidInputs in, ReadInputs(store, surface, options));
  std::vector<LevelTiles> levels =
      NonEmpty(MakeLevels(
                   in, options, [](const TileKey&) { return true; }, {}, nullptr),
               in);
  TileBuildReport report;
  report.pyramid = in.pyramid;
  TB_RETURN_IF_ERROR(WritePyramid(store, in.pyramid, levels, options.extensions.metadata, &report));
  return report;
}

namespace {

// The options a pyramid was built with, from its row.
Result<TileBuildOptions> OptionsOf(const TilePyramidInfo& pyramid) {
  TileBuildOptions options;
  options.max_zoom = pyramid.max_zoom;
  TB_ASSIGN_OR_RETURN(options.extensions, ParseTileExtensions(pyramid.extensions));
  options.water_tag = pyramid.water_tag;
  return options;
}

// The longitude/latitude box of the union of the changes' regions (store CRS), its edges
// densified so a curved image of a straight edge stays inside, grown by a hair for round-off.
Result<TileRect> ChangedRegion(const std::vector<Change>& changes, const Crs& crs) {
  TB_ASSIGN_OR_RETURN(Crs wgs84, Crs::FromUserInput("EPSG:4326"));
  std::vector<TinVertex> ring;
  constexpr int kSteps = 16;
  for (const Change& c : changes)
    for (int i = 0; i <= kSteps; ++i) {
      const double t = static_cast<double>(i) / kSteps;
      const double x = c.min_x + t * (c.max_x - c.min_x);
      const double y = c.min_y + t * (c.max_y - c.min_y);
      for (const auto& [px, py] : {std::pair{x, c.min_y}, std::pair{x, c.max_y},
                                   std::pair{c.min_x, y}, std::pair{c.max_x, y}})
        ring.push_back({px, py, 0, VertexKind::kDem});
    }
  TB_RETURN_IF_ERROR(ReprojectXy(crs, wgs84, ring));
  TileRect box{180, 90, -180, -90};
  for (const TinVertex& v : ring) {
    box.west = std::min(box.west, v.x), box.east = std::max(box.east, v.x);
    box.south = std::min(box.south, v.y), box.north = std::max(box.north, v.y);
  }
  constexpr double kHair = 1e-6;  // degrees, about 0.1 m
  box.west -= kHair, box.south -= kHair, box.east += kHair, box.north += kHair;
  return box;
}

bool Meets(const TileRect& a, const TileRect& b) {
  return a.west <= b.east && b.west <= a.east && a.south <= b.north && b.south <= a.north;
}

}  // namespace

Result<TileUpdateReport> UpdateTilePyramid(Store& store, const SurfaceInfo& surface) {
  TileStore tiles(store.db());
  TB_ASSIGN_OR_RETURN(const std::optional<TilePyramidInfo> old, tiles.Pyramid(surface.id));
  if (!old)
    return Status::InvalidArgument("surface '" + surface.name +
                                   "' has no tiles to update (run tinbase tiles build first)");
  TileUpdateReport report;
  report.since_tx = report.tx = old->tx;
  TB_ASSIGN_OR_RETURN(const std::vector<Change> all, ChangesSince(store, old->tx));
  std::vector<Change> changes;
  for (const Change& c : all)
    if (c.surface == surface.id) changes.push_back(c);
  report.changes = static_cast<int64_t>(changes.size());
  if (changes.empty()) return report;

  TB_ASSIGN_OR_RETURN(const TileBuildOptions options, OptionsOf(*old));
  TB_ASSIGN_OR_RETURN(const PyramidInputs in, ReadInputs(store, surface, options));
  report.tx = in.pyramid.tx;
  if (in.pyramid.min_height != old->min_height || in.pyramid.max_height != old->max_height) {
    TB_ASSIGN_OR_RETURN(const TileBuildReport rebuilt, BuildTilePyramid(store, surface, options));
    report.full_rebuild = true;
    for (const TileLevelReport& l : rebuilt.levels) report.tiles_rewritten += l.tiles;
    return report;
  }
  TB_ASSIGN_OR_RETURN(std::optional<Crs> crs, store.GetCrs());
  TB_ASSIGN_OR_RETURN(const TileRect region, ChangedRegion(changes, *crs));
  const auto wanted = [&](const TileKey& key) { return Meets(RectOf(key), region); };
  TB_ASSIGN_OR_RETURN(std::set<TileKey> keys, tiles.Keys(surface.id));
  std::set<TileKey> stale;
  for (const TileKey& key : keys)
    if (wanted(key)) stale.insert(key);
  // Unchanged children of the tiles made again are read from the store, decoded once.
  std::map<TileKey, std::optional<QuantizedMesh>> read;
  Status read_error;
  const auto stored = [&](const TileKey& key) -> const QuantizedMesh* {
    auto it = read.find(key);
    if (it == read.end()) {
      std::optional<QuantizedMesh> mesh;
      Result<std::optional<std::pair<std::vector<uint8_t>, int64_t>>> tile =
          tiles.Tile(surface.id, key);
      if (!tile.ok()) {
        read_error = tile.status();
      } else if (tile->has_value()) {
        Result<QuantizedMesh> decoded = DecodeQuantizedMesh((*tile)->first, key.ToString());
        if (decoded.ok()) {
          mesh = std::move(*decoded);
        } else {
          read_error = Status::Corruption("stored tile " + decoded.status().message());
        }
      }
      it = read.emplace(key, std::move(mesh)).first;
    }
    return it->second ? &*it->second : nullptr;
  };
  std::vector<LevelTiles> levels = NonEmpty(MakeLevels(in, options, wanted, stale, stored), in);
  TB_RETURN_IF_ERROR(read_error);

  for (const TileKey& key : stale) keys.erase(key);
  for (const LevelTiles& level : levels)
    for (const auto& [key, mesh] : level.meshes) keys.insert(key);

  TB_ASSIGN_OR_RETURN(auto tx, store.BeginWrite());
  for (const TileKey& key : stale) {
    bool remade = false;
    for (const LevelTiles& level : levels) remade = remade || level.meshes.count(key) > 0;
    if (remade) continue;
    TB_RETURN_IF_ERROR(tiles.DeleteTile(surface.id, key));
    ++report.tiles_deleted;
  }
  std::set<TileKey> meeting = stale;
  for (LevelTiles& level : levels)
    for (auto& [key, mesh] : level.meshes) {
      if (options.extensions.metadata && key.level % kMetadataAvailability == 0)
        mesh.metadata = MetadataOf(keys, key);
      TB_ASSIGN_OR_RETURN(const std::vector<uint8_t> bytes, EncodeQuantizedMesh(mesh));
      TB_RETURN_IF_ERROR(tiles.PutTile(surface.id, key, bytes, in.pyramid.tx));
      ++report.tiles_rewritten;
      meeting.insert(key);
    }
  TB_RETURN_IF_ERROR(tiles.SetPyramidTx(surface.id, in.pyramid.tx));
  TB_RETURN_IF_ERROR(tx->Commit());
  report.tiles_meeting = static_cast<int64_t>(meeting.size());
  return report;
}

Result<std::vector<std::pair<SurfaceInfo, TileUpdateReport>>> UpdateAllTilePyramids(Store& store) {
  TB_ASSIGN_OR_RETURN(const std::vector<SurfaceInfo> surfaces, SurfaceStore(store).List());
  std::vector<std::pair<SurfaceInfo, TileUpdateReport>> out;
  TileStore tiles(store.db());
  for (const SurfaceInfo& surface : surfaces) {
    TB_ASSIGN_OR_RETURN(const std::optional<TilePyramidInfo> pyramid, tiles.Pyramid(surface.id));
    if (!pyramid) continue;
    TB_ASSIGN_OR_RETURN(TileUpdateReport report, UpdateTilePyramid(store, surface));
    out.emplace_back(surface, report);
  }
  return out;
}

Result<nlohmann::json> LayerJson(Store& store, const SurfaceInfo& surface) {
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  TileStore tiles(store.db());
  TB_ASSIGN_OR_RETURN(const std::optional<TilePyramidInfo> pyramid, tiles.Pyramid(surface.id));
  if (!pyramid)
    return Status::NotFound("surface '" + surface.name +
                            "' has no tiles (run tinbase tiles build first)");
  TB_ASSIGN_OR_RETURN(const std::set<TileKey> keys, tiles.Keys(surface.id));
  TB_ASSIGN_OR_RETURN(const auto levels, tiles.Levels(surface.id));
  double west = 180, south = 90, east = -180, north = -90;
  for (const TileKey& k : keys) {
    if (k.level != pyramid->max_zoom) continue;
    const TileRect r = RectOf(k);
    west = std::min(west, r.west), south = std::min(south, r.south);
    east = std::max(east, r.east), north = std::max(north, r.north);
  }
  nlohmann::json errors = nlohmann::json::array();
  for (const auto& [level, error] : levels) errors.push_back(error);
  nlohmann::json layer = {
      {"tilejson", "2.1.0"},
      {"name", surface.name},
      {"description", "tinbase surface '" + surface.name + "'"},
      {"version", "1.0.0"},
      {"format", "quantized-mesh-1.0"},
      {"scheme", "tms"},
      {"tiles", {"{z}/{x}/{y}.terrain?v={version}"}},
      {"projection", "EPSG:4326"},
      {"bounds", {west, south, east, north}},
      {"minzoom", 0},
      {"maxzoom", pyramid->max_zoom},
      {"available", AvailableJson(keys, 0, pyramid->max_zoom)},
      {"tinbase", {{"geometricError", errors}, {"tx", pyramid->tx}}},
  };
  nlohmann::json extensions = nlohmann::json::array();
  TB_ASSIGN_OR_RETURN(const TileExtensions built, ParseTileExtensions(pyramid->extensions));
  if (built.normals) extensions.push_back("octvertexnormals");
  if (built.water_mask) extensions.push_back("watermask");
  if (built.metadata) {
    extensions.push_back("metadata");
    layer["metadataAvailability"] = kMetadataAvailability;
  }
  layer["extensions"] = extensions;
  return layer;
}

Status ExportTiles(Store& store, const SurfaceInfo& surface, const std::string& dir, bool gzip) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(dir, ec) && !(fs::is_directory(dir, ec) && fs::is_empty(dir, ec)))
    return Status::IOError("cannot write tiles to '" + dir + "': it exists and is not empty");
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  TB_ASSIGN_OR_RETURN(const nlohmann::json layer, LayerJson(store, surface));
  const fs::path temp = dir + ".partial-" + std::to_string(getpid());
  fs::remove_all(temp, ec);
  Status written = [&]() -> Status {
    fs::create_directories(temp, ec);
    if (ec) return Status::IOError("cannot create '" + temp.string() + "': " + ec.message());
    const std::string text = layer.dump(2);
    TB_RETURN_IF_ERROR(
        WriteFile(temp / "layer.json", std::vector<uint8_t>(text.begin(), text.end())));
    TileStore tiles(store.db());
    TB_ASSIGN_OR_RETURN(const std::set<TileKey> keys, tiles.Keys(surface.id));
    for (const TileKey& key : keys) {
      TB_ASSIGN_OR_RETURN(auto tile, tiles.Tile(surface.id, key));
      if (!tile) return Status::Corruption("tile " + key.ToString() + " vanished during export");
      const fs::path folder = temp / std::to_string(key.level) / std::to_string(key.x);
      fs::create_directories(folder, ec);
      if (ec) return Status::IOError("cannot create '" + folder.string() + "': " + ec.message());
      std::vector<uint8_t> bytes = std::move(tile->first);
      if (gzip) {
        TB_ASSIGN_OR_RETURN(bytes, Gzip(bytes));
      }
      TB_RETURN_IF_ERROR(WriteFile(folder / (std::to_string(key.y) + ".terrain"), bytes));
    }
    fs::remove(dir, ec);  // an empty directory, or nothing
    fs::rename(temp, dir, ec);
    if (ec) return Status::IOError("cannot move the tiles to '" + dir + "': " + ec.message());
    return Status::Ok();
  }();
  if (!written.ok()) fs::remove_all(temp, ec);
  return written;
}

}  // namespace tinbase
