// Kernel: `import landxml` (a LandXML 1.2 surface into a new surface of the store).
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "core/import/landxml_reader.h"
#include "db/import/landxml_import.h"
#include "db/store.h"

namespace tinbase::cli {

namespace {

struct ImportLandXmlArgs {
  std::string store;
  std::string file;
  std::string surface;
  std::string dem;
  bool json = false;
};

int RunImportLandXml(const ImportLandXmlArgs& args) {
  Stopwatch watch;
  // The file is read and checked whole before the store is opened for writing.
  auto file = ReadLandXml(args.file);
  if (!file.ok()) return ReportError(file.status());
  auto store = Store::Open(args.store, Store::Access::kReadWrite);
  if (!store.ok()) return ReportError(store.status());
  LandXmlImportOptions options;
  options.surface = args.surface;
  if (!args.dem.empty()) options.dem = args.dem;
  auto report = ImportLandXml(**store, *file, options);
  if (!report.ok()) return ReportError(report.status().WithContext(args.file));
  if (args.json) {
    nlohmann::json j = {{"surface", report->surface.name},
                        {"id", report->surface.id},
                        {"kind", SurfaceKindName(report->surface.kind)},
                        {"vertices", report->vertices},
                        {"triangles", report->triangles},
                        {"features", report->features},
                        {"constraints", report->constraints},
                        {"tx", report->tx}};
    std::cout << j.dump() << "\n";
  } else {
    std::cout << "imported surface '" << report->surface.name << "' from " << args.file << ": "
              << report->vertices << " vertices, " << report->triangles << " triangles, "
              << report->features << " features in " << Num(watch.Seconds(), 3) << " s\n";
  }
  return kExitOk;
}

}  // namespace

void RegisterImportCommands(CLI::App& app, int* exit_code) {
  CLI::App* import = app.add_subcommand("import", "Read a surface from a file");
  import->require_subcommand(1);
  auto args = std::make_shared<ImportLandXmlArgs>();
  CLI::App* landxml = import->add_subcommand(
      "landxml", "A LandXML 1.2 surface (Surfaces/Surface/Definition) as a new surface");
  landxml->add_option("store", args->store, "Store file")->required();
  landxml->add_option("file", args->file, "LandXML file")->required();
  landxml->add_option("--surface", args->surface, "Name of the new surface (default: the file's)");
  landxml->add_option("--dem", args->dem,
                      "Drape on this DEM of the store (its nodata hides triangles)");
  landxml->add_flag("--json", args->json, "Print the result as JSON");
  landxml->callback([=] { *exit_code = RunImportLandXml(*args); });
}

}  // namespace tinbase::cli
