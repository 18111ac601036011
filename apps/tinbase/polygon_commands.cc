// Kernels: `polygon add` (features from any OGR source into a surface, one transaction or one
// per feature), `polygon remove` and `polygon update` (one feature, locally).
#include <iostream>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "apps/tinbase/progress.h"
#include "db/polygon_editor.h"
#include "db/tiles/tile_pyramid.h"

namespace tinbase::cli {

namespace {

// With --update-tiles, after the edit committed: every pyramid brought up to date in its own
// transaction (a failure there leaves the tiles as they were; `tiles update` catches up).
int UpdateTilesAfterEdit(Store& store, bool wanted, int exit_code) {
  if (!wanted || exit_code != kExitOk) return exit_code;
  auto updated = UpdateAllTilePyramids(store);
  if (!updated.ok()) return ReportError(updated.status().WithContext("the edit committed; tiles"));
  for (const auto& [surface, r] : *updated)
    std::cout << "tiles of '" << surface.name << "': " << r.tiles_rewritten << " rewritten, "
              << r.tiles_deleted << " deleted" << (r.full_rebuild ? " (all rebuilt)" : "") << "\n";
  return kExitOk;
}

struct AddArgs {
  std::string store;
  bool update_tiles = false;
  PolygonAddOptions options;
  std::string mode;  // parsed into options.mode by the handler
  double level = 0;
  std::string z_from = "dem";  // parsed into options.z_from by the handler
};

// --mode's text as a FeatureMode: the one place a polygon command reads a mode string.
Status ParseModeOption(const std::string& text, PolygonAddOptions* options) {
  if (text.empty()) return Status::Ok();  // update: keep the feature's mode
  TB_ASSIGN_OR_RETURN(options->mode, ParseFeatureMode(text));
  return Status::Ok();
}

int RunAdd(AddArgs args, bool level_given) {
  if (Status s = ParseModeOption(args.mode, &args.options); !s.ok()) return ReportError(s);
  auto z_from = ParseZFrom(args.z_from);
  if (!z_from.ok()) return ReportError(z_from.status().WithContext("--z-from"));
  args.options.z_from = *z_from;
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  if (level_given) args.options.level = args.level;
  Stopwatch watch;
  auto report = WithProgress("polygon add", [&](std::function<void(double)> progress) {
    args.options.progress = std::move(progress);
    return AddPolygons(**store, args.options);
  });
  if (!report.ok()) return ReportError(report.status());
  for (const std::string& failure : report->failures)
    std::cerr << "tinbase: not added: " << failure << "\n";
  std::cout << "added " << report->features << " " << args.mode << " feature(s) to '"
            << args.options.surface << "' (" << report->ring_vertices
            << " draped ring vertices): " << report->removed << " triangles replaced by "
            << report->added << ", " << report->visible << " of them visible; transaction "
            << report->tx << " in " << Num(watch.Seconds(), 3) << " s\n";
  return UpdateTilesAfterEdit(**store, args.update_tiles,
                              report->failures.empty() ? kExitOk : kExitFailure);
}

struct EditArgs {
  std::string store;
  bool update_tiles = false;
  int64_t id = 0;
  PolygonAddOptions options;
  std::string mode;  // update: parsed into options.mode by the handler; empty keeps the old one
  double level = 0;
};

void PrintEdit(const char* verb, int64_t id, const PolygonAddReport& r, double seconds) {
  std::cout << verb << " feature " << id << ": " << r.removed << " triangles replaced by "
            << r.added << " (" << r.refinement_points << " refinement points), " << r.visible
            << " of them visible; transaction " << r.tx << " in " << Num(seconds, 3) << " s\n";
}

int RunRemove(const EditArgs& args) {
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  Stopwatch watch;
  auto report = RemovePolygon(**store, args.id);
  if (!report.ok()) return ReportError(report.status());
  PrintEdit("removed", args.id, *report, watch.Seconds());
  return UpdateTilesAfterEdit(**store, args.update_tiles, kExitOk);
}

int RunUpdate(EditArgs args, bool level_given) {
  if (Status s = ParseModeOption(args.mode, &args.options); !s.ok()) return ReportError(s);
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  if (level_given) args.options.level = args.level;
  Stopwatch watch;
  auto report = UpdatePolygon(**store, args.id, args.options);
  if (!report.ok()) return ReportError(report.status());
  PrintEdit("updated", args.id, *report, watch.Seconds());
  std::cout << "the new geometry is feature " << report->first_feature_id << "\n";
  return UpdateTilesAfterEdit(**store, args.update_tiles, kExitOk);
}

}  // namespace

void RegisterPolygonCommands(CLI::App& app, int* exit_code) {
  CLI::App* polygon = app.add_subcommand("polygon", "Geological polygons and breaklines");
  polygon->require_subcommand(1);
  auto args = std::make_shared<AddArgs>();
  CLI::App* add = polygon->add_subcommand("add", "Insert features from a vector file");
  add->add_option("store", args->store, "Store file")->required();
  add->add_option("file", args->options.file, "Vector file (GeoJSON, GeoPackage, shapefile, ...)")
      ->required();
  add->add_option("--surface", args->options.surface, "Surface name")->required();
  add->add_option("--mode", args->mode, "clip, erase, fill, replace, breakline or softline")
      ->required();
  add->add_option("--z-from", args->z_from,
                  "Lines: dem (draped, the default) or feature (each vertex keeps its own z)");
  add->add_option("--layer", args->options.layer, "Layer name (default: the only layer)");
  add->add_option("--where", args->options.where, "OGR attribute filter, e.g. \"code = 'A-b'\"");
  add->add_option("--tag-field", args->options.tag_field, "Field whose value tags the triangles");
  add->add_option("--tag", args->options.tag, "One tag for every feature");
  CLI::Option* level = add->add_option("--level", args->level, "replace: the flat z in metres");
  add->add_flag("--repair", args->options.repair,
                "Repair invalid polygons with GEOS MakeValid before validating them");
  add->add_flag("--each", args->options.each,
                "Commit feature by feature; report the features that failed and why");
  add->add_flag("--update-tiles", args->update_tiles,
                "Then bring the tile pyramids up to date (tinbase tiles update)");
  add->callback([=] { *exit_code = RunAdd(*args, level->count() > 0); });

  auto remove_args = std::make_shared<EditArgs>();
  CLI::App* remove =
      polygon->add_subcommand("remove", "Remove a feature, re-triangulating locally");
  remove->add_option("store", remove_args->store, "Store file")->required();
  remove->add_option("id", remove_args->id, "Feature id")->required();
  remove->add_flag("--update-tiles", remove_args->update_tiles,
                   "Then bring the tile pyramids up to date (tinbase tiles update)");
  remove->callback([=] { *exit_code = RunRemove(*remove_args); });

  auto update_args = std::make_shared<EditArgs>();
  CLI::App* update = polygon->add_subcommand(
      "update", "Replace a feature's geometry by a file's features (merged), locally");
  update->add_option("store", update_args->store, "Store file")->required();
  update->add_option("id", update_args->id, "Feature id")->required();
  update->add_option("file", update_args->options.file, "Vector file")->required();
  update->add_option("--mode", update_args->mode, "New mode (default: the old one)");
  update->add_option("--layer", update_args->options.layer, "Layer name");
  update->add_option("--where", update_args->options.where, "OGR attribute filter");
  update->add_option("--tag-field", update_args->options.tag_field, "Field giving the tag");
  update->add_option("--tag", update_args->options.tag, "The tag (default: the old one)");
  update->add_flag("--repair", update_args->options.repair,
                   "Repair invalid polygons with GEOS MakeValid before validating them");
  CLI::Option* update_level =
      update->add_option("--level", update_args->level, "replace: the flat z in metres");
  update->add_flag("--update-tiles", update_args->update_tiles,
                   "Then bring the tile pyramids up to date (tinbase tiles update)");
  update->callback([=] { *exit_code = RunUpdate(*update_args, update_level->count() > 0); });
}

}  // namespace tinbase::cli
