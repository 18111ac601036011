// Kernel: `points import` (a LAS or XYZ point file to a Delaunay surface, optionally thinned).
#include <cmath>
#include <iostream>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "apps/tinbase/progress.h"
#include "db/point_import.h"

namespace tinbase::cli {

namespace {

struct ImportArgs {
  std::string store;
  PointImportOptions options;
  std::vector<int> classes;
  double max_cell_area = 0;
  std::string density;  // "COUNT/AREA"
};

// Parses --density "COUNT/AREA" (the paper's "10 per 150 square feet" is "10/150").
Result<DensityWindow> ParseDensityWindow(const std::string& text) {
  const auto bad = [&](const std::string& why) {
    return Status::InvalidArgument("--density '" + text + "': " + why +
                                   " (expected COUNT/AREA, e.g. 10/150)");
  };
  const size_t slash = text.find('/');
  if (slash == std::string::npos) return bad("no '/'");
  DensityWindow window;
  size_t used = 0;
  try {
    window.max_points = std::stod(text.substr(0, slash), &used);
    if (used != slash) return bad("the count is not a number");
    const std::string area = text.substr(slash + 1);
    window.area = std::stod(area, &used);
    if (used != area.size()) return bad("the area is not a number");
  } catch (const std::exception&) {
    return bad("not a number");
  }
  if (!(std::isfinite(window.max_points) && window.max_points >= 0)) {
    return bad("the count must be >= 0");
  }
  if (!(std::isfinite(window.area) && window.area > 0)) return bad("the area must be positive");
  return window;
}

int RunImport(ImportArgs args) {
  for (int c : args.classes) {
    if (c < 0 || c > 255)
      return ReportError(Status::InvalidArgument("--class " + std::to_string(c) +
                                                 " is not a LAS class (0 to 255)"));
    args.options.classes.insert(static_cast<uint8_t>(c));
  }
  if (args.max_cell_area > 0) args.options.thresholds.max_cell_area = args.max_cell_area;
  if (!args.density.empty()) {
    if (args.max_cell_area > 0) {
      return ReportError(
          Status::InvalidArgument("--density and --max-cell-area are two ways to say dense: "
                                  "give one"));
    }
    auto window = ParseDensityWindow(args.density);
    if (!window.ok()) return ReportError(window.status());
    args.options.thresholds.window = *window;
  }
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  Stopwatch watch;
  auto report = WithProgress("points import", [&](std::function<void(double)> progress) {
    args.options.progress = std::move(progress);
    return ImportPoints(**store, args.options);
  });
  if (!report.ok()) return ReportError(report.status());
  const PointTinReport& p = report->points;
  std::cout << "surface '" << args.options.surface << "' from " << p.format << ": " << p.points_in
            << " points in, " << p.selected << " selected (" << p.classes << "), " << p.duplicates
            << " duplicates, " << p.dropped << " thinned out, " << p.kept << " kept, "
            << p.triangles << " triangles";
  if (!p.reprojected_from.empty()) std::cout << "; reprojected from " << p.reprojected_from;
  if (report->adopted_crs) std::cout << "; the store takes its CRS " << report->crs;
  std::cout << " (" << Num(watch.Seconds(), 3) << " s)\n";
  return kExitOk;
}

}  // namespace

void RegisterPointsCommands(CLI::App& app, int* exit_code) {
  CLI::App* points = app.add_subcommand("points", "LiDAR and other point clouds");
  points->require_subcommand(1);
  auto args = std::make_shared<ImportArgs>();
  CLI::App* import = points->add_subcommand("import", "Triangulate a LAS or XYZ file as a surface");
  import->add_option("store", args->store, "Store file")->required();
  import->add_option("file", args->options.file, "LAS 1.0-1.4 (uncompressed) or XYZ text")
      ->required();
  import->add_option("--surface", args->options.surface, "Name of the new surface")->required();
  import->add_option(
      "--class", args->classes,
      "LAS classes to keep (repeatable; default: ground = 2 when present, else all)");
  import->add_flag("--thin", args->options.thin, "Voronoi density thinning (paper 003)");
  import
      ->add_option("--vertical-threshold", args->options.thresholds.vertical_threshold,
                   "--thin: drop a dense point within this z of its Voronoi neighbours")
      ->check(CLI::NonNegativeNumber);
  import
      ->add_option("--max-cell-area", args->max_cell_area,
                   "--thin: cells smaller than this are dense (default 0.75 x median)")
      ->check(CLI::PositiveNumber);
  import->add_option("--density", args->density,
                     "--thin: dense where more than COUNT points lie in the disc of AREA around "
                     "a point, as COUNT/AREA (paper 003: 10/150 in square feet)");
  import->callback([=] { *exit_code = RunImport(*args);
});
}  // namespace tinbase::cli

}  // namespace tinbase::cli
