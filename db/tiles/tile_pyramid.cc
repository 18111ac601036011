// Tile pyramid: see tile_pyramid.h.
#include "db/tiles/tile_pyramid.h"

#include <unistd.h>
#include <zlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>

#include "core/tiles/availability.h"
#include "core/tiles/level_surfaces.h"
#include "db/change_log.h"
#include "db/tiles/pyramid_levels.h"

namespace tinbase {

namespace {

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
