// Kernels: `polygon add` (features from any OGR source into a surface, one transaction or one
// per feature), `polygon remove` and `polygon update` (one feature, locally).
#include <iostream>
#include <nlohmann/json.hpp>

#include "apps/tinbase/command.h"
#include "apps/tinbase/edit_tiles.h"
#include "apps/tinbase/output.h"
#include "apps/tinbase/progress.h"
#include "db/polygon_editor.h"

namespace tinbase::cli {

namespace {

struct AddArgs {
  std::string store;
  EditTiles tiles;
  bool json = false;
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

// What was cut off overhanging polygons and which were skipped, as warnings on stderr.
void PrintOverhangs(const PolygonAddReport& r) {
  for (const OverhangCut& cut : r.clipped)
    std::cerr << "tinbase: clipped to the surface's data area: " << cut.label << " (feature "
              << cut.feature << "), " << Num(cut.area_outside, 6) << " square units outside\n";
  for (const std::string& skipped : r.skipped) std::cerr << "tinbase: skipped: " << skipped << "\n";
}

nlohmann::json AddJson(const PolygonAddReport& r, const EditTiles& tiles) {
  nlohmann::json out = {{"tx", r.tx},
                        {"features", r.feature_ids},
                        {"ring_vertices", r.ring_vertices},
                        {"removed", r.removed},
                        {"added", r.added},
                        {"visible", r.visible},
                        {"failures", r.failures},
                        {"clipped", OverhangCutsJson(r.clipped)},
                        {"skipped", r.skipped}};
  if (tiles.wanted) out["tiles_updated"] = TilesTouched(tiles.updates);
  return out;
}

int RunAdd(AddArgs args, bool level_given) {
  if (Status s = ParseModeOption(args.mode, &args.options); !s.ok()) return ReportError(s);
  auto z_from = ParseZFrom(args.z_from);
  if (!z_from.ok()) return ReportError(z_from.status().WithContext("--z-from"));
  args.options.z_from = *z_from;
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  if (level_given) args.options.level = args.level;
  args.options.before_commit = args.tiles.Hook();
  Stopwatch watch;
  auto report = WithProgress("polygon add", [&](std::function<void(double)> progress) {
    args.options.progress = std::move(progress);
    return AddPolygons(**store, args.options);
  });
  if (!report.ok()) return ReportError(report.status());
  for (const std::string& failure : report->failures)
    std::cerr << "tinbase: not added: " << failure << "\n";
  PrintOverhangs(*report);
  const int exit_code = report->failures.empty() ? kExitOk : kExitFailure;
  if (args.json) {
    std::cout << AddJson(*report, args.tiles).dump() << "\n";
    return exit_code;
  }
  std::cout << "added " << report->features << " " << args.mode << " feature(s) to '"
            << args.options.surface << "' (" << report->ring_vertices
            << " draped ring vertices): " << report->removed << " triangles replaced by "
            << report->added << ", " << report->visible << " of them visible; transaction "
            << report->tx << " in " << Num(watch.Seconds(), 3) << " s\n";
  args.tiles.Print();
  return exit_code;
}

struct EditArgs {
  std::string store;
  EditTiles tiles;
  int64_t id = 0;
  PolygonAddOptions options;
  std::string mode;  // update: parsed into options.mode by the handler; empty keeps the old one
  double level = 0;
  std::string z_from;  // update: parsed into options.z_from; empty keeps the old feature's
};

void PrintEdit(const char* verb, int64_t id, const PolygonAddReport& r, double seconds) {
  std::cout << verb << " feature " << id << ": " << r.removed << " triangles replaced by "
            << r.added << " (" << r.refinement_points << " refinement points), " << r.visible
            << " of them visible; transaction " << r.tx << " in " << Num(seconds, 3) << " s\n";
}

int RunRemove(EditArgs args) {
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  Stopwatch watch;
  auto report = RemovePolygon(**store, args.id, args.tiles.Hook());
  if (!report.ok()) return ReportError(report.status());
  PrintEdit("removed", args.id, *report, watch.Seconds());
  args.tiles.Print();
  return kExitOk;
}

int RunUpdate(EditArgs args, bool level_given) {
  if (Status s = ParseModeOption(args.mode, &args.options); !s.ok()) return ReportError(s);
  if (!args.z_from.empty()) {
    auto z_from = ParseZFrom(args.z_from);
    if (!z_from.ok()) return ReportError(z_from.status().WithContext("--z-from"));
    args.options.z_from = *z_from;
    args.options.z_from_given = true;
  }
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  if (level_given) args.options.level = args.level;
  args.options.before_commit = args.tiles.Hook();
  Stopwatch watch;
  auto report = UpdatePolygon(**store, args.id, args.options);
  if (!report.ok()) return ReportError(report.status());
  PrintOverhangs(*report);
  PrintEdit("updated", args.id, *report, watch.Seconds());
  std::cout << "the new geometry is feature " << report->first_feature_id << "\n";
  args.tiles.Print();
  return kExitOk;
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
  add->add_flag("--update-tiles", args->tiles.wanted,
                "Bring the tile pyramids up to date in the edit's own transaction");
  add->add_flag("--strict", args->options.strict,
                "Refuse polygons that overhang the surface's data area instead of clipping them");
  add->add_flag("--json", args->json, "Print the report as JSON");
  add->callback([=] { *exit_code = RunAdd(*args, level->count() > 0); });

  auto remove_args = std::make_shared<EditArgs>();
  CLI::App* remove =
      polygon->add_subcommand("remove", "Remove a feature, re-triangulating locally");
  remove->add_option("store", remove_args->store, "Store file")->required();
  remove->add_option("id", remove_args->id, "Feature id")->required();
  remove->add_flag("--update-tiles", remove_args->tiles.wanted,
                   "Bring the tile pyramids up to date in the edit's own transaction");
  remove->callback([=] { *exit_code = RunRemove(*remove_args); });

  auto update_args = std::make_shared<EditArgs>();
  CLI::App* update = polygon->add_subcommand(
      "update", "Replace a feature's geometry by a file's features (merged), locally");
  update->add_option("store", update_args->store, "Store file")->required();
  update->add_option("id", update_args->id, "Feature id")->required();
  update->add_option("file", update_args->options.file, "Vector file")->required();
  update->add_option("--mode", update_args->mode,
                     "New mode: clip, erase, fill, replace, breakline or softline (default: the "
                     "old one)");
  update->add_option("--z-from", update_args->z_from,
                     "Lines: dem (draped) or feature (own z); default: the old feature's");
  update->add_option("--layer", update_args->options.layer, "Layer name");
  update->add_option("--where", update_args->options.where, "OGR attribute filter");
  update->add_option("--tag-field", update_args->options.tag_field, "Field giving the tag");
  update->add_option("--tag", update_args->options.tag, "The tag (default: the old one)");
  update->add_flag("--repair", update_args->options.repair,
                   "Repair invalid polygons with GEOS MakeValid before validating them");
  CLI::Option* update_level =
      update->add_option("--level", update_args->level, "replace: the flat z in metres");
  update->add_flag("--update-tiles", update_args->tiles.wanted,
                   "Bring the tile pyramids up to date in the edit's own transaction");
  update->add_flag(
      "--strict", update_args->options.strict,
      "Refuse a polygon that overhangs the surface's data area instead of clipping it");
  update->callback([=] { *exit_code = RunUpdate(*update_args, update_level->count() > 0); });
}

}  // namespace tinbase::cli
