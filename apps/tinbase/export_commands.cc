// Kernel: `export` (a surface, or the part of it a selection picks, to obj, ply, stl, glb,
// geojson, gpkg, landxml or vdb). The selection options mean what they mean everywhere
// (db/query/surface_selection.h); the file goes through OutputFile, so a failed export leaves
// nothing behind.
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "apps/tinbase/command.h"
#include "apps/tinbase/landxml_vdb_export.h"
#include "apps/tinbase/output.h"
#include "apps/tinbase/progress.h"
#include "core/base/output_file.h"
#include "core/export/export_format.h"
#include "core/export/tin_export.h"
#include "db/export/export_features.h"
#include "db/export/gpkg_export.h"
#include "db/feature_store.h"
#include "db/history/as_of.h"
#include "db/query/surface_selection.h"
#include "db/surface_store.h"

namespace tinbase::cli {

namespace {

struct ExportArgs {
  std::string store;
  std::string surface;
  std::string format;  // empty: from the output's extension
  std::string output;
  std::string bbox;
  int64_t feature = 0;
  bool visible_only = false;
  std::string tag;
  bool json = false;
  std::string base;             // vdb
  double voxel = 0;             // vdb
  std::optional<double> floor;  // vdb
  std::string dem;              // gpkg: the DEM of the raster layer ("none": no raster)
  // --as-of: the surface as it was after this transaction.
  std::optional<int64_t> as_of;
};

// The formats that read more of the store than the selected mesh (features, constraints, a
// second surface, the DEM), written by their own kernels: "gpkg", "landxml" or "vdb", from
// --format or the extension; empty for the mesh formats.
std::string StoreFormat(const ExportArgs& args) {
  const auto ends_with = [&](const char* ext) {
    const std::string e(ext);
    return args.output.size() > e.size() &&
           args.output.compare(args.output.size() - e.size(), e.size(), e) == 0;
  };
  if (args.format == "gpkg" || args.format == "landxml" || args.format == "vdb") return args.format;
  if (args.format.empty() && ends_with(".gpkg")) return "gpkg";
  if (args.format.empty() && ends_with(".xml")) return "landxml";
  if (args.format.empty() && ends_with(".vdb")) return "vdb";
  return "";
}

// Every format the command writes, for messages.
std::string AllFormats() { return ExportFormatList() + ", gpkg, landxml, vdb"; }

// --format, or else the output file's extension.
Result<ExportFormat> ResolveFormat(const ExportArgs& args) {
  if (!args.format.empty()) {
    Result<ExportFormat> format = ParseExportFormat(args.format);
    if (!format.ok())
      return Status::InvalidArgument("unknown export format '" + args.format +
                                     "' (expected one of: " + AllFormats() + ")");
    return format;
  }
  if (auto format = ExportFormatFromPath(args.output)) return *format;
  return Status::InvalidArgument("cannot tell the format from '" + args.output +
                                 "': give --format (one of: " + AllFormats() + ")");
}

Result<SurfaceFilter> FilterOf(const ExportArgs& args) {
  SurfaceFilter filter;
  if (!args.bbox.empty()) {
    Result<Box> box = ParseBbox(args.bbox);
    if (!box.ok()) return box.status().WithContext("--bbox");
    filter.bbox = *box;
  }
  filter.feature = args.feature;
  filter.visible_only = args.visible_only;
  if (!args.tag.empty()) filter.tag = args.tag;
  return filter;
}

// The named surface, or without --surface the one that holds --feature.
Result<SurfaceInfo> ResolveSurface(Store& store, const ExportArgs& args) {
  SurfaceStore surfaces(store);
  if (!args.surface.empty()) return surfaces.Find(args.surface);
  TB_ASSIGN_OR_RETURN(std::vector<SurfaceInfo> all, surfaces.List());
  for (const SurfaceInfo& s : all)
    if (LoadFeature(store, s, args.feature).ok()) return s;
  return Status::NotFound("no feature " + std::to_string(args.feature));
}

// --format gpkg (db/export/gpkg_export.h): triangles, features, constraints and the DEM.
int RunGpkgExport(const ExportArgs& args) {
  if (args.surface.empty()) return ReportError(Status::InvalidArgument("give --surface"));
  GpkgExportOptions options;
  auto filter = FilterOf(args);
  if (!filter.ok()) return ReportError(filter.status());
  options.filter = *filter;
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
  const std::string store_format = StoreFormat(args);
  if (store_format != "vdb" && (!args.base.empty() || args.voxel != 0 || args.floor))
    return ReportError(
        Status::InvalidArgument("--base, --voxel and --floor apply only to --format vdb"));
  if (store_format != "gpkg" && !args.dem.empty())
    return ReportError(Status::InvalidArgument("--dem applies only to --format gpkg"));
  if (!store_format.empty() && args.as_of)
    return ReportError(Status::InvalidArgument("--as-of applies to the mesh formats (" +
                                               ExportFormatList() + "), not to " + store_format));
  if (store_format == "gpkg") return RunGpkgExport(args);
  if (!store_format.empty()) {
    auto filter = FilterOf(args);
    if (!filter.ok()) return ReportError(filter.status());
    LandXmlVdbExportArgs a{args.store, args.surface, args.output, *filter,
                           args.base,  args.voxel,   args.floor};
    return store_format == "landxml" ? RunLandXmlExport(a) : RunVdbExport(a);
  }
  auto format = ResolveFormat(args);
  if (!format.ok()) return ReportError(format.status());
  auto filter = FilterOf(args);
  if (!filter.ok()) return ReportError(filter.status());
  if (args.surface.empty() && args.feature == 0)
    return ReportError(Status::InvalidArgument("give --surface (or --feature alone)"));
  // Before any reading, so a bad path costs nothing; ExportTin checks again when it writes.
  if (auto out = OutputFile::Create(args.output); !out.ok()) return ReportError(out.status());
  // --as-of goes back inside a write transaction that is dropped, never committed.
  auto store =
      Store::Open(args.store, args.as_of ? Store::Access::kReadWrite : Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  auto crs = (*store)->GetCrs();
  if (!crs.ok()) return ReportError(crs.status());
  Stopwatch watch;
  // Two stages, reading the selection and writing the file; the bar shows which one runs.
  ProgressBar bar(std::string("export ") + ExportFormatName(*format));
  auto surface = ResolveSurface(**store, args);
  if (!surface.ok()) return ReportError(surface.status());
  std::unique_ptr<WriteTransaction> past;  // dropped at return: the store stays as it is
  if (args.as_of) {
    auto begun = BeginAsOf(**store, *surface, *args.as_of);
    if (!begun.ok()) return ReportError(begun.status());
    past = std::move(*begun);
  }
  auto selected = SelectSurface(**store, *surface, *filter);
  if (!selected.ok()) return ReportError(selected.status());
  bar.Update(0.5);

  ExportOptions options;
  options.format = *format;
  options.triangle_ids = selected->triangle_ids;
  if (*format == ExportFormat::kGlb) {
    if (Status s = AddExportFeatures(**store, *surface, selected->tin, options); !s.ok())
      return ReportError(s);
  }
  auto report = ExportTin(selected->tin, crs->has_value() ? &**crs : nullptr, args.output, options);
  if (!report.ok()) return ReportError(report.status());
  bar.Finish();
  if (args.json) {
    const nlohmann::json j = {{"output", args.output},        {"format", ExportFormatName(*format)},
                              {"surface", surface->name},     {"selection", filter->Describe()},
                              {"vertices", report->vertices}, {"triangles", report->triangles},
                              {"bytes", report->bytes},       {"seconds", watch.Seconds()}};
    std::cout << j.dump(2) << "\n";
    return kExitOk;
  }
  std::cout << "wrote " << args.output << " (" << ExportFormatName(*format)
            << "): " << report->vertices << " vertices, " << report->triangles << " triangles, "
            << report->bytes << " bytes in " << Num(watch.Seconds(), 3) << " s\n";
  return kExitOk;
}

}  // namespace

void RegisterExportCommands(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* cmd = app.add_subcommand("export", "Write a surface to a file (" + AllFormats() + ")");
  cmd->add_option("store", args->store, "Store file")->required();
  cmd->add_option("--surface", args->surface,
                  "Surface name (may be left out with --feature: the feature's surface)");
  cmd->add_option("--format", args->format,
                  AllFormats() + " (default: from the output file's extension)");
  cmd->add_option("-o,--output", args->output, "Output file")->required();
  cmd->add_option("--bbox", args->bbox, "Only triangles meeting MINX,MINY,MAXX,MAXY");
  cmd->add_option("--feature", args->feature,
                  "Only the inside of this polygon feature, clipped to it, holes left out");
  cmd->add_flag("--visible-only", args->visible_only, "Leave out invisible triangles");
  cmd->add_option("--tag", args->tag, "Only triangles with this tag");
  cmd->add_flag("--json", args->json, "Print what was written as JSON");
  cmd->add_option("--base", args->base, "vdb: lower surface; writes the thickness as a fog volume");
  cmd->add_option("--voxel", args->voxel, "vdb: voxel size (default: the longer side / 512)");
  cmd->add_option("--floor", args->floor, "vdb level set: z of the floor under the surface");
  cmd->add_option("--dem", args->dem,
                  "gpkg: DEM of the raster layer (default the surface's; none: no raster)");
  cmd->add_option("--as-of", args->as_of,
                  "The surface as it was after this transaction (mesh formats; see `changes`)");
  cmd->callback([=] { *exit_code = RunExport(*args); });
}

}  // namespace tinbase::cli
