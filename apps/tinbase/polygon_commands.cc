// Kernel: `polygon add` (features from any OGR source into a surface, one transaction).
#include <iostream>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "db/polygon_editor.h"

namespace tinbase::cli {

namespace {

struct AddArgs {
  std::string store;
  PolygonAddOptions options;
  double level = 0;
};

int RunAdd(AddArgs args, bool level_given) {
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  if (level_given) args.options.level = args.level;
  Stopwatch watch;
  auto report = AddPolygons(**store, args.options);
  if (!report.ok()) return ReportError(report.status());
  std::cout << "added " << report->features << " " << args.options.mode << " feature(s) to '"
            << args.options.surface << "' (" << report->ring_vertices
            << " draped ring vertices): " << report->removed << " triangles replaced by "
            << report->added << ", " << report->visible << " visible; transaction " << report->tx
            << " in " << Num(watch.Seconds(), 3) << " s\n";
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
  add->add_option("--mode", args->options.mode, "clip, erase, fill, replace or breakline")
      ->required();
  add->add_option("--layer", args->options.layer, "Layer name (default: the only layer)");
  add->add_option("--where", args->options.where, "OGR attribute filter, e.g. \"code = 'A-b'\"");
  add->add_option("--tag-field", args->options.tag_field, "Field whose value tags the triangles");
  add->add_option("--tag", args->options.tag, "One tag for every feature");
  CLI::Option* level = add->add_option("--level", args->level, "replace: the flat z in metres");
  add->callback([=] { *exit_code = RunAdd(*args, level->count() > 0); });
}

}  // namespace tinbase::cli
