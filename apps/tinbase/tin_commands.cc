// Kernel: `tin build` (a terrain surface from a stored DEM, by greedy insertion or edge collapse).
#include <iostream>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "db/surface_builder.h"

namespace tinbase::cli {

namespace {

struct BuildArgs {
  std::string store;
  SurfaceBuildOptions options;
  std::string strategy = "quadric";
};

int RunBuild(const BuildArgs& args) {
  SurfaceBuildOptions options = args.options;
  if (!ParseCollapseStrategy(args.strategy, &options.collapse.strategy)) {
    return ReportError(Status::InvalidArgument("unknown collapse strategy '" + args.strategy +
                                               "' (known: quadric, paper)"));
  }
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  auto report = BuildSurfaceFromDem(**store, options);
  if (!report.ok()) return ReportError(report.status());
  std::cout << "surface '" << report->surface.name << "' (" << report->surface.method << "): "
            << report->vertices << " vertices, " << report->triangles << " triangles; max error "
            << Num(report->quality.max_error, 4) << " m, RMS " << Num(report->quality.rms_error, 4)
            << " m; built in " << Num(report->build_seconds, 3) << " s, written in "
            << Num(report->write_seconds, 3) << " s (transaction " << report->tx << ")\n";
  if (options.method == "collapse" && !report->collapse.budget_met) {
    std::cout << "note: no allowed collapse was left at " << report->collapse.faces_out
              << " faces, above the budget of " << options.collapse.faces
              << " (the outline's corners and plan-view validity come first)\n";
  }
  return kExitOk;
}

}  // namespace

void RegisterTinCommands(CLI::App& app, int* exit_code) {
  CLI::App* tin = app.add_subcommand("tin", "Terrain TIN builders");
  tin->require_subcommand(1);
  auto args = std::make_shared<BuildArgs>();
  CLI::App* build = tin->add_subcommand("build", "Build a terrain surface from a DEM");
  build->add_option("store", args->store, "Store file")->required();
  build->add_option("--surface", args->options.surface, "Name of the new surface")->required();
  build->add_option("--method", args->options.method,
                    "Builder: greedy or rtin (to a tolerance), vip (to a significance "
                    "threshold) or collapse (to a face budget)");
  build->add_option("--threshold", args->options.vip_threshold,
                    "vip: keep cells at least this significant, in metres (default 1)");
  build->add_option("--dem", args->options.dem, "DEM name (default: the only DEM)");
  build->add_option("--tolerance", args->options.greedy.tolerance,
                    "Largest vertical error in metres (default 1)");
  build->add_option("--max-points", args->options.greedy.max_points,
                    "Stop at this many vertices (default: no limit)");
  build->add_option("--faces", args->options.collapse.faces,
                    "collapse: the face budget, at least 2");
  build->add_option("--strategy", args->strategy,
                    "collapse: quadric (Garland-Heckbert, default) or paper (short, flat, low "
                    "degree first; vertices stay DEM samples)");
  build->callback([=] { *exit_code = RunBuild(*args); });
}

}  // namespace tinbase::cli
