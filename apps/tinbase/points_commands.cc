// Kernels: `points import` (a LAS or XYZ point file to a Delaunay surface, optionally thinned),
// `points add` and `points remove` (survey points into and out of an existing surface,
// db/edit/mass_points.h).
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "apps/tinbase/command.h"
#include "apps/tinbase/edit_tiles.h"
#include "apps/tinbase/output.h"
#include "apps/tinbase/progress.h"
#include "db/edit/mass_points.h"
#include "db/point_import.h"
#include "db/query/surface_selection.h"

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

struct AddArgs {
  std::string store;
  PointsAddOptions options;
  std::string tag;
  bool json = false;
  EditTiles tiles;
};

struct RemoveArgs {
  std::string store;
  int64_t feature = 0;
  std::string surface;
  std::string bbox;
  bool json = false;
  EditTiles tiles;
};

nlohmann::json ReportJson(const PointsReport& r, const EditTiles& tiles) {
  nlohmann::json out = {{"tx", r.tx},
                        {"points_in", r.points_in},
                        {"vertices", r.inserted},
                        {"snapped", r.snapped},
                        {"features_added", r.features_added},
                        {"features_removed", r.features_removed},
                        {"triangles_removed", r.removed},
                        {"triangles_added", r.added},
                        {"refinement_points", r.refinement_points},
                        {"reprojected_from", r.reprojected_from}};
  if (tiles.wanted) out["tiles_updated"] = TilesTouched(tiles.updates);
  return out;
}

int RunAdd(AddArgs args) {
  if (!args.tag.empty()) args.options.tag = args.tag;
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  args.options.before_commit = args.tiles.Hook();
  Stopwatch watch;
  auto report = AddPoints(**store, args.options);
  if (!report.ok()) return ReportError(report.status());
  if (args.json) {
    std::cout << ReportJson(*report, args.tiles).dump(2) << "\n";
    return kExitOk;
  }
  for (const std::string& snapped : report->snapped) std::cerr << "tinbase: " << snapped << "\n";
  std::cout << "added " << report->inserted << " of " << report->points_in << " survey points to '"
            << args.options.surface << "' as feature " << report->features_added.front() << " ("
            << report->snapped.size() << " snapped onto a vertex and left out): " << report->removed
            << " triangles replaced by " << report->added << " (" << report->refinement_points
            << " refinement points); transaction " << report->tx << " in "
            << Num(watch.Seconds(), 3) << " s\n";
  args.tiles.Print();
  return kExitOk;
}

int RunRemove(RemoveArgs args, bool feature_given) {
  PointsRemoveOptions options;
  options.before_commit = args.tiles.Hook();
  if (feature_given) options.feature = args.feature;
  if (!args.bbox.empty()) {
    if (args.surface.empty()) return ReportError(Status::InvalidArgument("--bbox needs --surface"));
    auto box = ParseBbox(args.bbox);
    if (!box.ok()) return ReportError(box.status());
    options.box = *box;
    options.surface = args.surface;
  }
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  Stopwatch watch;
  auto report = RemovePoints(**store, options);
  if (!report.ok()) return ReportError(report.status());
  if (args.json) {
    std::cout << ReportJson(*report, args.tiles).dump(2) << "\n";
    return kExitOk;
  }
  std::cout << "removed " << report->inserted << " survey point vertices of "
            << report->features_removed.size() << " feature(s)";
  if (!report->features_added.empty())
    std::cout << " (the points left are feature " << report->features_added.front() << ")";
  std::cout << ": " << report->removed << " triangles replaced by " << report->added << " ("
            << report->refinement_points << " refinement points); transaction " << report->tx
            << " in " << Num(watch.Seconds(), 3) << " s\n";
  args.tiles.Print();
  return kExitOk;
}

// --update-tiles on an edit command: the tiles in the edit's own transaction.
void AddUpdateTilesFlag(CLI::App* command, EditTiles* tiles) {
  command->add_flag("--update-tiles", tiles->wanted,
                    "Bring the tile pyramids up to date in the edit's own transaction");
}

void RegisterEditCommands(CLI::App* points, int* exit_code) {
  auto add_args = std::make_shared<AddArgs>();
  CLI::App* add = points->add_subcommand(
      "add", "Insert survey points with their own z into a surface, locally (one transaction)");
  add->add_option("store", add_args->store, "Store file")->required();
  add->add_option("file", add_args->options.file,
                  "XYZ/CSV text, LAS, or a vector file of Point Z features (GeoJSON, ...)")
      ->required();
  add->add_option("--surface", add_args->options.surface, "Surface name")->required();
  add->add_option("--tag", add_args->tag, "Name of the points feature");
  add->add_flag("--json", add_args->json, "The report as JSON");
  AddUpdateTilesFlag(add, &add_args->tiles);
  add->callback([=] { *exit_code = RunAdd(*add_args); });

  auto remove_args = std::make_shared<RemoveArgs>();
  CLI::App* remove = points->add_subcommand(
      "remove", "Take survey points out of a surface, locally (one transaction)");
  remove->add_option("store", remove_args->store, "Store file")->required();
  CLI::Option* feature =
      remove->add_option("--feature", remove_args->feature, "A points feature, whole");
  CLI::Option* bbox = remove->add_option("--bbox", remove_args->bbox,
                                         "Or the survey points in MINX,MINY,MAXX,MAXY");
  feature->excludes(bbox);
  remove->add_option("--surface", remove_args->surface, "The surface (with --bbox)");
  remove->add_flag("--json", remove_args->json, "The report as JSON");
  AddUpdateTilesFlag(remove, &remove_args->tiles);
  remove->callback([=] { *exit_code = RunRemove(*remove_args, feature->count() > 0); });
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
RegisterEditCommands(points, exit_code);
}  // namespace tinbase::cli

}  // namespace tinbase::cli
