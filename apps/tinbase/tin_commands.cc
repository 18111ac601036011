// Kernel: `tin build` (a terrain surface from a stored DEM by one of the builders of
// core/tin/terrain_builder.h). --method's text is parsed here into a TerrainMethod, once.
#include <algorithm>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "apps/tinbase/progress.h"
#include "db/surface_builder.h"

namespace tinbase::cli {

namespace {

struct BuildArgs {
  std::string store;
  SurfaceBuildOptions options;
  std::string method = "greedy";  // parsed into options.method by the handler
  std::string strategy = "quadric";
  // Method-specific options the user gave, with the methods they apply to: one given to a
  // method that would ignore it is an error, not a silent no-op.
  std::vector<std::pair<CLI::Option*, std::vector<TerrainMethod>>> method_options;
};

Status CheckMethodOptions(const BuildArgs& args, TerrainMethod method) {
  for (const auto& [option, methods] : args.method_options) {
    if (option->count() == 0 || std::find(methods.begin(), methods.end(), method) != methods.end())
      continue;
    std::string list;
    for (TerrainMethod m : methods)
      list += (list.empty() ? "" : " or ") + std::string(TerrainMethodName(m));
    return Status::InvalidArgument(option->get_name() + " applies only to --method " + list +
                                   ", not " + TerrainMethodName(method));
  }
  return Status::Ok();
}

int RunBuild(const BuildArgs& args) {
  auto method = ParseTerrainMethod(args.method);
  if (!method.ok()) return ReportError(method.status());
  if (Status s = CheckMethodOptions(args, *method); !s.ok()) return ReportError(s);
  SurfaceBuildOptions options = args.options;
  options.method = *method;
  if (!ParseCollapseStrategy(args.strategy, &options.collapse.strategy)) {
    return ReportError(Status::InvalidArgument("unknown collapse strategy '" + args.strategy +
                                               "' (known: quadric, paper)"));
  }
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  auto report = WithProgress("tin build", [&](std::function<void(double)> progress) {
    options.progress = std::move(progress);
    return BuildSurfaceFromDem(**store, options);
  });
  if (!report.ok()) return ReportError(report.status());
  std::cout << "surface '" << report->surface.name << "' (" << report->surface.method
            << "): " << report->vertices << " vertices, " << report->triangles
            << " triangles; max error " << Num(report->quality.max_error, 4) << " m, RMS "
            << Num(report->quality.rms_error, 4) << " m; built in " << Num(report->build_seconds, 3)
            << " s, written in " << Num(report->write_seconds, 3) << " s (transaction "
            << report->tx << ")\n";
  if (options.method == TerrainMethod::kCollapse && !report->collapse.budget_met) {
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
  build->add_option("--method", args->method,
                    "Builder: greedy or rtin (to a tolerance), vip (to a significance "
                    "threshold) or collapse (to a face budget)");
  CLI::Option* threshold =
      build->add_option("--threshold", args->options.vip_threshold,
                        "vip: keep cells at least this significant, in metres (default 1)");
  build->add_option("--dem", args->options.dem, "DEM name (default: the only DEM)");
  CLI::Option* tolerance = build->add_option("--tolerance", args->options.greedy.tolerance,
                                             "greedy, rtin: largest vertical error in metres "
                                             "(default 1)");
  CLI::Option* max_points = build->add_option("--max-points", args->options.greedy.max_points,
                                              "greedy, vip: stop at this many vertices (default: "
                                              "no limit)");
  CLI::Option* faces = build->add_option("--faces", args->options.collapse.faces,
                                         "collapse: the face budget, at least 2");
  CLI::Option* strategy =
      build->add_option("--strategy", args->strategy,
                        "collapse: quadric (Garland-Heckbert, default) or paper (short, flat, low "
                        "degree first; vertices stay DEM samples)");
  args->method_options = {{threshold, {TerrainMethod::kVip}},
                          {tolerance, {TerrainMethod::kGreedy, TerrainMethod::kRtin}},
                          {max_points, {TerrainMethod::kGreedy, TerrainMethod::kVip}},
                          {faces, {TerrainMethod::kCollapse}},
                          {strategy, {TerrainMethod::kCollapse}}};
  build->callback([=] { *exit_code = RunBuild(*args); });
}

}  // namespace tinbase::cli
