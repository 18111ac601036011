// Kernel: `export` (a surface, or the inside of one polygon feature, to OBJ or GeoJSON).
#include <iostream>

#include "apps/tinbase/command.h"
#include "apps/tinbase/landxml_vdb_export.h"
#include "apps/tinbase/output.h"
#include "core/export/tin_export.h"
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
  std::string base;             // vdb
  double voxel = 0;             // vdb
  std::optional<double> floor;  // vdb
};

int RunExport(const ExportArgs& args) {
  if (args.format == "landxml" || args.format == "vdb") {
    LandXmlVdbExportArgs a{args.store, args.surface, args.output, {},
                           args.base,  args.voxel,   args.floor};
    a.filter.feature = args.feature;
    a.filter.visible_only = args.visible_only;
    return args.format == "landxml" ? RunLandXmlExport(a) : RunVdbExport(a);
  }
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
  cmd->add_option("--format", args->format, "obj, geojson, landxml or vdb (default obj)");
  cmd->add_option("-o,--output", args->output, "Output file")->required();
  cmd->add_flag("--visible-only", args->visible_only, "Leave out invisible triangles");
  cmd->add_option("--base", args->base, "vdb: lower surface; writes the thickness as a fog volume");
  cmd->add_option("--voxel", args->voxel, "vdb: voxel size (default: the longer side / 512)");
  cmd->add_option("--floor", args->floor, "vdb level set: z of the floor under the surface");
  cmd->callback([=] { *exit_code = RunExport(*args); });
}

}  // namespace tinbase::cli
