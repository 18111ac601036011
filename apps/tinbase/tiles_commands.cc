// Kernels: `tiles build` (a surface's quantized-mesh pyramid into the store), `tiles update`
// (only the tiles the edits since touched), `tiles export`
// (the pyramid as a static z/x/y.terrain tree with layer.json), `tiles info` (what a pyramid
// holds; with --verify every tile is decoded and checked) and `tiles make` (one tile made on
// demand from the surface, written to a file or compared with the stored one).
#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "apps/tinbase/progress.h"
#include "core/base/output_file.h"
#include "core/tiles/quantized_mesh.h"
#include "db/tiles/tile_pyramid.h"

namespace tinbase::cli {

namespace {

struct TilesArgs {
  std::string store;
  std::string surface;
  std::optional<int> max_zoom;  // unset: the surface's natural zoom
  std::string extensions;
  std::string water_tag;
  std::string output;
  bool gzip = false;
  bool json = false;
  bool verify = false;
  std::optional<int64_t> window_triangles;  // unset: the default
  std::string tile;                         // z/x/y
  int repeat = 1;
};

// "z/x/y" (as in a tile URL) -> TileKey. InvalidArgument naming the text otherwise.
Result<TileKey> ParseTileKey(const std::string& text) {
  TileKey key;
  const char* p = text.c_str();
  std::array<int64_t, 3> parts{};
  for (size_t i = 0; i < parts.size(); ++i) {
    char* end = nullptr;
    errno = 0;
    parts[i] = std::strtoll(p, &end, 10);
    const char expected = i + 1 < parts.size() ? '/' : '\0';
    if (end == p || errno != 0 || *end != expected || parts[i] < 0)
      return Status::InvalidArgument("--tile '" + text + "': expected z/x/y (three whole numbers)");
    p = end + (expected == '/' ? 1 : 0);
  }
  if (parts[0] > kMaxTileLevel)
    return Status::InvalidArgument("--tile '" + text + "': level over " +
                                   std::to_string(kMaxTileLevel));
  key.level = static_cast<int>(parts[0]);
  key.x = parts[1];
  key.y = parts[2];
  return key;
}

Result<SurfaceInfo> FindSurface(Store& store, const std::string& name) {
  if (name.empty()) return Status::InvalidArgument("give --surface");
  return SurfaceStore(store).Find(name);
}

int RunBuild(const TilesArgs& args) {
  auto extensions = ParseTileExtensions(args.extensions);
  if (!extensions.ok()) return ReportError(extensions.status());
  TileBuildOptions options;
  options.extensions = *extensions;
  // Any value given is checked by the build (0..24), -1 included.
  if (args.max_zoom) options.max_zoom = *args.max_zoom;
  if (!args.water_tag.empty()) options.water_tag = args.water_tag;
  if (args.window_triangles && *args.window_triangles < 1)
    return ReportError(Status::InvalidArgument("--window-triangles must be positive"));
  if (args.window_triangles) options.window_triangles = *args.window_triangles;
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  auto surface = FindSurface(**store, args.surface);
  if (!surface.ok()) return ReportError(surface.status());
  Stopwatch watch;
  auto report = WithProgress("tiles build", [&](std::function<void(double)> progress) {
    options.progress = std::move(progress);
    return BuildTilePyramid(**store, *surface, options);
  });
  if (!report.ok()) return ReportError(report.status());
  int64_t tiles = 0, bytes = 0;
  nlohmann::json levels = nlohmann::json::array();
  for (const TileLevelReport& l : report->levels) {
    tiles += l.tiles, bytes += l.bytes;
    levels.push_back({{"level", l.level},
                      {"geometric_error", l.geometric_error},
                      {"tiles", l.tiles},
                      {"triangles", l.triangles},
                      {"bytes", l.bytes}});
  }
  if (args.json) {
    std::cout << nlohmann::json{{"surface", surface->name},
                                {"max_zoom", report->pyramid.max_zoom},
                                {"extensions", report->pyramid.extensions},
                                {"tx", report->pyramid.tx},
                                {"tiles", tiles},
                                {"bytes", bytes},
                                {"seconds", watch.Seconds()},
                                {"levels", levels}}
                     .dump(2)
              << "\n";
    return kExitOk;
  }
  std::cout << "tiles of surface '" << surface->name << "': levels 0-" << report->pyramid.max_zoom
            << ", " << tiles << " tiles, " << bytes << " bytes in " << Num(watch.Seconds(), 3)
            << " s\n";
  return kExitOk;
}

int RunUpdate(const TilesArgs& args) {
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  auto surface = FindSurface(**store, args.surface);
  if (!surface.ok()) return ReportError(surface.status());
  Stopwatch watch;
  auto report = UpdateTilePyramid(**store, *surface);
  if (!report.ok()) return ReportError(report.status());
  if (args.json) {
    std::cout << nlohmann::json{{"surface", surface->name},
                                {"since_tx", report->since_tx},
                                {"tx", report->tx},
                                {"changes", report->changes},
                                {"full_rebuild", report->full_rebuild},
                                {"tiles_meeting", report->tiles_meeting},
                                {"tiles_rewritten", report->tiles_rewritten},
                                {"tiles_deleted", report->tiles_deleted},
                                {"read_seconds", report->read_seconds},
                                {"make_seconds", report->make_seconds},
                                {"write_seconds", report->write_seconds},
                                {"seconds", watch.Seconds()}}
                     .dump(2)
              << "\n";
    return kExitOk;
  }
  if (report->changes == 0) {
    std::cout << "tiles of surface '" << surface->name << "' are up to date (transaction "
              << report->tx << ")\n";
    return kExitOk;
  }
  std::cout << "tiles of surface '" << surface->name << "': " << report->changes
            << " change(s) since transaction " << report->since_tx << ", "
            << (report->full_rebuild ? "the height range moved: all rebuilt, " : "")
            << report->tiles_rewritten << " tiles rewritten, " << report->tiles_deleted
            << " deleted in " << Num(watch.Seconds(), 3) << " s\n";
  return kExitOk;
}

int RunExport(const TilesArgs& args) {
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  auto surface = FindSurface(**store, args.surface);
  if (!surface.ok()) return ReportError(surface.status());
  if (Status s = ExportTiles(**store, *surface, args.output, args.gzip); !s.ok())
    return ReportError(s);
  std::cout << "wrote " << args.output << "\n";
  return kExitOk;
}

int RunInfo(const TilesArgs& args) {
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  auto surface = FindSurface(**store, args.surface);
  if (!surface.ok()) return ReportError(surface.status());
  auto layer = LayerJson(**store, *surface);
  if (!layer.ok()) return ReportError(layer.status());
  TileStore tiles((*store)->db());
  auto count = tiles.CountAndBytes(surface->id);
  if (!count.ok()) return ReportError(count.status());
  int64_t decoded = 0;
  if (args.verify) {
    auto keys = tiles.Keys(surface->id);
    if (!keys.ok()) return ReportError(keys.status());
    for (const TileKey& key : *keys) {
      auto tile = tiles.Tile(surface->id, key);
      if (!tile.ok()) return ReportError(tile.status());
      auto mesh = DecodeQuantizedMesh((*tile)->first, "tile " + key.ToString());
      if (!mesh.ok()) return ReportError(mesh.status());
      ++decoded;
    }
  }
  nlohmann::json out = {{"surface", surface->name},
                        {"tiles", count->first},
                        {"bytes", count->second},
                        {"layer", *layer}};
  if (args.verify) out["decoded"] = decoded;
  if (args.json) {
    std::cout << out.dump(2) << "\n";
  } else {
    std::cout << "surface '" << surface->name << "': " << count->first << " tiles, "
              << count->second << " bytes, levels 0-" << (*layer)["maxzoom"].get<int>();
    if (args.verify) std::cout << ", all " << decoded << " decode";
    std::cout << "\n";
  }
  return kExitOk;
}

int RunMake(const TilesArgs& args) {
  auto key = ParseTileKey(args.tile);
  if (!key.ok()) return ReportError(key.status());
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  auto surface = FindSurface(**store, args.surface);
  if (!surface.ok()) return ReportError(surface.status());
  if (args.repeat < 1) return ReportError(Status::InvalidArgument("--repeat must be positive"));
  std::vector<uint8_t> bytes;
  double seconds = 0;
  for (int i = 0; i < args.repeat; ++i) {
    Stopwatch watch;
    auto made = MakeTile(**store, *surface, *key);
    if (!made.ok()) return ReportError(made.status());
    seconds = i == 0 ? watch.Seconds() : std::min(seconds, watch.Seconds());
    bytes = std::move(*made);
  }
  auto stored = TileStore((*store)->db()).Tile(surface->id, *key);
  if (!stored.ok()) return ReportError(stored.status());
  const bool same = stored->has_value() && (*stored)->first == bytes;
  if (!args.output.empty()) {
    auto file = OutputFile::Create(args.output);
    if (!file.ok()) return ReportError(file.status());
    std::ofstream out(file->temp_path(), std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) return ReportError(Status::IOError("cannot write '" + args.output + "'"));
    const Status committed = file->Commit();
    if (!committed.ok()) return ReportError(committed);
  }
  if (args.json) {
    std::cout << nlohmann::json{{"surface", surface->name},
                                {"tile", key->ToString()},
                                {"bytes", bytes.size()},
                                {"seconds", seconds},
                                {"same_as_stored", same}}
                     .dump(2)
              << "\n";
    return kExitOk;
  }
  std::cout << "tile " << key->ToString() << " of surface '" << surface->name
            << "': " << bytes.size() << " bytes in " << Num(seconds, 3) << " s, "
            << (same ? "the same as" : "not the same as") << " the stored tile\n";
  return kExitOk;
}

}  // namespace

void RegisterTilesCommands(CLI::App& app, int* exit_code) {
  CLI::App* tiles = app.add_subcommand("tiles", "Quantized-mesh terrain tiles of a surface");
  tiles->require_subcommand(1);

  auto build = std::make_shared<TilesArgs>();
  CLI::App* b = tiles->add_subcommand("build", "Build a surface's tile pyramid into the store");
  b->add_option("store", build->store, "Store file")->required();
  b->add_option("--surface", build->surface, "Surface name")->required();
  b->add_option("--max-zoom", build->max_zoom,
                "Finest level, 0-24 (default: where a tile holds about 128 vertex spacings)");
  b->add_option("--extensions", build->extensions,
                "Comma-separated: octvertexnormals, watermask, metadata");
  b->add_option("--water-tag", build->water_tag,
                "Tag of the features that are water (for the watermask extension)");
  b->add_option("--window-triangles", build->window_triangles,
                "About how many triangles the build reads at a time (bounds its memory)");
  b->add_flag("--json", build->json, "Print the report as JSON");
  b->callback([=] { *exit_code = RunBuild(*build); });

  auto update = std::make_shared<TilesArgs>();
  CLI::App* u = tiles->add_subcommand(
      "update", "Rebuild the tiles the edits since the last build or update touched");
  u->add_option("store", update->store, "Store file")->required();
  u->add_option("--surface", update->surface, "Surface name")->required();
  u->add_flag("--json", update->json, "Print the report as JSON");
  u->callback([=] { *exit_code = RunUpdate(*update); });

  auto exp = std::make_shared<TilesArgs>();
  CLI::App* e = tiles->add_subcommand("export", "Write the tiles as a z/x/y.terrain tree");
  e->add_option("store", exp->store, "Store file")->required();
  e->add_option("--surface", exp->surface, "Surface name")->required();
  e->add_option("-o,--output", exp->output, "Output directory (new or empty)")->required();
  e->add_flag("--gzip", exp->gzip, "Gzip every tile (serve with Content-Encoding: gzip)");
  e->callback([=] { *exit_code = RunExport(*exp); });

  auto info = std::make_shared<TilesArgs>();
  CLI::App* i = tiles->add_subcommand("info", "What a surface's pyramid holds");
  i->add_option("store", info->store, "Store file")->required();
  i->add_option("--surface", info->surface, "Surface name")->required();
  i->add_flag("--verify", info->verify, "Decode every tile");
  i->add_flag("--json", info->json, "Print JSON (with layer.json)");
  i->callback([=] { *exit_code = RunInfo(*info); });

  auto make = std::make_shared<TilesArgs>();
  CLI::App* m = tiles->add_subcommand(
      "make", "Make one tile on demand from the surface (compared with the stored one)");
  m->add_option("store", make->store, "Store file")->required();
  m->add_option("--surface", make->surface, "Surface name")->required();
  m->add_option("--tile", make->tile, "The tile as z/x/y (TMS y)")->required();
  m->add_option("-o,--output", make->output, "Write the tile's bytes to this file");
  m->add_option("--repeat", make->repeat, "Make it this many times; report the fastest");
  m->add_flag("--json", make->json, "Print the report as JSON");
  m->callback([=] { *exit_code = RunMake(*make); });
}

}  // namespace tinbase::cli
