// Pyramid levels: see pyramid_levels.h.
#include "db/tiles/pyramid_levels.h"

#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "core/geometry/reproject.h"
#include "core/tiles/availability.h"
#include "core/tiles/coarse_tile.h"
#include "db/mesh/mesh_tables.h"

namespace tinbase {

namespace {

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
std::map<TileKey, std::optional<QuantizedMesh>> MergeKeys(
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

CoarseTileOptions CoarseOptions(const PyramidInputs& in, int level) {
  CoarseTileOptions coarse;
  coarse.error = LevelError(in, level);
  coarse.min_height = in.pyramid.min_height;
  coarse.max_height = in.pyramid.max_height;
  return coarse;
}

}  // namespace

std::pair<double, double> QuantisationRange(double min, double max) {
  if (!(max > min)) max = min + 1;
  return {min, max};
}

HeightExtremes ExtremesOf(const LoadedSurface& surface, const Crs& crs) {
  const std::vector<TinVertex>& v = surface.tin.vertices;
  size_t lo = 0, hi = 0;
  for (size_t i = 1; i < v.size(); ++i) {
    if (v[i].z < v[lo].z) lo = i;
    if (v[i].z > v[hi].z) hi = i;
  }
  const double metres = crs.VerticalMetresPerUnit();
  HeightExtremes out;
  std::tie(out.min, out.max) = QuantisationRange(v[lo].z * metres, v[hi].z * metres);
  out.min_vertex = surface.vertex_ids[lo];
  out.max_vertex = surface.vertex_ids[hi];
  return out;
}

Result<SurfaceSummary> Summarise(Store& store, const SurfaceInfo& surface, const Crs& crs,
                                 bool geographic) {
  TB_ASSIGN_OR_RETURN(const Crs wgs84, Crs::FromUserInput("EPSG:4326"));
  MeshTables tables(store.db(), surface);
  TB_ASSIGN_OR_RETURN(VertexCursor cursor, tables.Vertices());
  SurfaceSummary out;
  out.west = out.south = std::numeric_limits<double>::infinity();
  out.east = out.north = -out.west;
  LoadedSurface ends;  // the lowest and the highest vertex so far, with their ids
  std::vector<TinVertex> chunk;
  constexpr size_t kChunk = size_t{1} << 16;
  const auto flush = [&]() -> Status {
    if (chunk.empty()) return Status::Ok();
    TB_RETURN_IF_ERROR(ReprojectXy(crs, wgs84, chunk));
    for (const TinVertex& v : chunk) {
      out.west = std::min(out.west, v.x), out.east = std::max(out.east, v.x);
      out.south = std::min(out.south, v.y), out.north = std::max(out.north, v.y);
    }
    chunk.clear();
    return Status::Ok();
  };
  int64_t id = 0;
  VertexRow row;
  while (true) {
    TB_ASSIGN_OR_RETURN(const bool more, cursor.Next(&id, &row));
    if (!more) break;
    if (ends.tin.vertices.empty()) {
      ends.tin.vertices = {row, row};
      ends.vertex_ids = {id, id};
    }
    if (row.z < ends.tin.vertices[0].z) ends.tin.vertices[0] = row, ends.vertex_ids[0] = id;
    if (row.z > ends.tin.vertices[1].z) ends.tin.vertices[1] = row, ends.vertex_ids[1] = id;
    ++out.vertices;
    if (!geographic) continue;
    chunk.push_back(row);
    if (chunk.size() == kChunk) TB_RETURN_IF_ERROR(flush());
  }
  TB_RETURN_IF_ERROR(flush());
  if (out.vertices == 0)
    return Status::NotFound("surface '" + surface.name + "' has no triangles to tile");
  out.extremes = ExtremesOf(ends, crs);
  return out;
}

const QuantizedMesh* StoredTiles::Get(const TileKey& key) {
  auto it = read_.find(key);
  if (it == read_.end()) it = read_.emplace(key, Read(key)).first;
  return it->second ? &*it->second : nullptr;
}

std::optional<QuantizedMesh> StoredTiles::Read(const TileKey& key) {
  Result<std::optional<std::pair<std::vector<uint8_t>, int64_t>>> tile = tiles_.Tile(surface_, key);
  if (!tile.ok()) {
    error_ = tile.status();
    return std::nullopt;
  }
  if (!tile->has_value()) return std::nullopt;
  Result<QuantizedMesh> decoded = DecodeQuantizedMesh((*tile)->first, key.ToString());
  if (!decoded.ok()) {
    error_ = Status::Corruption("stored tile " + decoded.status().message());
    return std::nullopt;
  }
  return std::move(*decoded);
}

int32_t TagIndex(const Tin& tin, const std::optional<std::string>& tag) {
  if (!tag) return kNoTag;
  for (size_t i = 0; i < tin.tags.size(); ++i)
    if (tin.tags[i] == *tag) return static_cast<int32_t>(i);
  return kNoTag;
}

double LevelError(const PyramidInputs& in, int level) {
  if (level == in.pyramid.max_zoom) return 0;
  return std::ldexp(in.base_error, in.pyramid.max_zoom - level - 1);
}

MadeLevels MakeLevels(const PyramidInputs& in, const TileBuildOptions& options,
                      const std::function<bool(const TileKey&)>& wanted,
                      const std::set<TileKey>& also,
                      const std::function<const QuantizedMesh*(const TileKey&)>& stored, int top) {
  const int max = in.pyramid.max_zoom;
  MadeLevels levels(max + 1);
  levels[max] =
      CutFinest(in.finest, max, in.water_tag, options.extensions.water_mask, wanted, also);
  // The finest level is most of the work; the write counts as one more level.
  const auto report = [&](int done) {
    if (options.progress) options.progress(0.5 * done / (max + 2.0) + (done > 0 ? 0.4 : 0.0));
  };
  report(1);
  for (int level = max - 1; level >= top; --level) {
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
    levels[level] = MergeLevel(in, options, parents, child);
  }
  return levels;
}

std::map<TileKey, std::optional<QuantizedMesh>> MergeLevel(
    const PyramidInputs& in, const TileBuildOptions& options, const std::set<TileKey>& parents,
    const std::function<const QuantizedMesh*(const TileKey&)>& child) {
  if (parents.empty()) return {};
  return MergeKeys(parents, CoarseOptions(in, parents.begin()->level),
                   options.extensions.water_mask, child);
}

std::vector<LevelTiles> NonEmpty(MadeLevels made, const PyramidInputs& in) {
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

}  // namespace tinbase
