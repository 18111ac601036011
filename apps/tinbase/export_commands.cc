// Kernel: `export` (a surface, or the inside of one polygon feature, to OBJ or GeoJSON).
#include <iostream>
#include <nlohmann/json.hpp>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "core/export/tin_export.h"
#include "db/export/gpkg_export.h"
#include "db/feature_store.h"
#include "db/surface_store.h"

namespace tinbase::cli {

namespace {

struct ExportArgs {
  std::string store;
  std::string surface;
  std::string format = "obj";
  std::string output;
  bool visible_only = false;
  int64_t feature = 0;
  std::string bbox;  // gpkg: the selection options of docs/cli.md
  std::string tag;
  std::string dem;  // gpkg: the DEM of the raster layer ("none": no raster)
  bool json = false;
};

// --format gpkg (db/export/gpkg_export.h): triangles, features, constraints and the DEM.
int RunGpkgExport(const ExportArgs& args) {
  if (args.surface.empty()) return ReportError(Status::InvalidArgument("give --surface"));
  GpkgExportOptions options;
  if (!args.bbox.empty()) {
    auto box = ParseBbox(args.bbox);
    if (!box.ok()) return ReportError(box.status().WithContext("--bbox"));
    options.filter.bbox = *box;
  }
  options.filter.feature = args.feature;
  options.filter.visible_only = args.visible_only;
  if (!args.tag.empty()) options.filter.tag = args.tag;
  options.with_dem = args.dem != "none";
  if (options.with_dem) options.dem = args.dem;
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  auto surface = SurfaceStore(**store).Find(args.surface);
  if (!surface.ok()) return ReportError(surface.status());
  auto report = ExportGpkg(**store, *surface, options, args.output);
  if (!report.ok()) return ReportError(report.status());
  nlohmann::json out = {{"output", args.output},
                        {"format", "gpkg"},
                        {"triangles", report->triangles},
                        {"vertices", report->vertices},
                        {"features", report->features},
                        {"breaklines", report->breaklines},
                        {"constraints", report->constraints}};
  out["dem"] = report->dem.empty() ? nlohmann::json(nullptr) : nlohmann::json(report->dem);
  if (report->raster)
    out["raster"] = {{"width", report->raster->width}, {"height", report->raster->height}};
  if (args.json) {
    std::cout << out.dump(2) << "\n";
  } else {
    std::cout << "wrote " << args.output << ": " << report->triangles << " triangles, "
              << report->features + report->breaklines << " features, " << report->constraints
              << " constraints"
              << (report->raster
                      ? ", DEM " + report->dem + " " + std::to_string(report->raster->width) +
                            " x " + std::to_string(report->raster->height)
                      : std::string())
              << "\n";
  }
  return kExitOk;
}

int RunExport(const ExportArgs& args) {
  if (args.format == "gpkg") return RunGpkgExport(args);
  auto format = ParseExportFormat(args.format);
  if (!format.ok()) return ReportError(format.status());
  if (args.surface.empty() == (args.feature == 0))
    return ReportError(Status::InvalidArgument("give --surface or --feature (one of them)"));
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  SurfaceStore surfaces(**store);
  auto crs = (*store)->GetCrs();
  if (!crs.ok()) return ReportError(crs.status());
  Stopwatch watch;
  auto loaded = [&]() -> Result<LoadedSurface> {
    if (args.feature != 0) return LoadFeatureSurface(**store, args.feature);
    TB_ASSIGN_OR_RETURN(SurfaceInfo surface, surfaces.Find(args.surface));
    return surfaces.Load(surface);
  }();
  if (!loaded.ok()) return ReportError(loaded.status());
  ExportOptions options;
  options.format = *format;
  options.visible_only = args.visible_only;
  options.triangle_ids = loaded->triangle_ids;
  auto report = ExportTin(loaded->tin, crs->has_value() ? &**crs : nullptr, args.output, options);
  if (!report.ok()) return ReportError(report.status());
  std::cout << "wrote " << args.output << ": " << report->vertices << " vertices, "
            << report->triangles << " triangles in " << Num(watch.Seconds(), 3) << " s\n";
  return kExitOk;
}

}  // namespace

void RegisterExportCommands(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* cmd = app.add_subcommand("export", "Write a surface to a file (obj, geojson)");
  cmd->add_option("store", args->store, "Store file")->required();
  cmd->add_option("--surface", args->surface, "Surface name");
  cmd->add_option("--feature", args->feature,
                  "Only the inside of this polygon feature, clipped to it, holes left out");
  cmd->add_option("--format", args->format, "obj or geojson (default obj)");
  cmd->add_option("-o,--output", args->output, "Output file")->required();
  cmd->add_flag("--visible-only", args->visible_only, "Leave out invisible triangles");
  cmd->add_option("--bbox", args->bbox, "gpkg: only triangles meeting minx,miny,maxx,maxy");
  cmd->add_option("--tag", args->tag, "gpkg: only triangles with this tag");
  cmd->add_option("--dem", args->dem,
                  "gpkg: DEM of the raster layer (default the surface's; none)");
  cmd->add_flag("--json", args->json, "gpkg: print the report as JSON");
  cmd->callback([=] { *exit_code = RunExport(*args); });
}

}  // namespace tinbase::cli
