// Kernel: `dem from-contours` (a blocked DEM from contour lines, paper 000's way).
#include <iostream>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "db/contour_import.h"

namespace tinbase::cli {

namespace {

struct FromContoursArgs {
  std::string store;
  ContourImportOptions options;
};

int RunFromContours(const FromContoursArgs& args) {
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  Stopwatch watch;
  auto report = ImportContourDem(**store, args.options);
  if (!report.ok()) return ReportError(report.status());
  const ContourDemReport& c = report->contours;
  const DemInfo& d = report->dem.dem;
  std::cout << "DEM '" << d.name << "' from " << c.lines << " contour lines (" << c.contour_vertices
            << " vertices, " << c.flat_triangles_found << " flat triangles repaired with "
            << c.steiner_points << " Steiner points, " << c.flat_triangles_left
            << " left): " << d.geometry.width << " x " << d.geometry.height << " cells, "
            << report->dem.blocks_written << " blocks"
            << (report->dem.warped ? ", warped onto the store's CRS" : "") << " in "
            << Num(watch.Seconds(), 3) << " s\n";
  return kExitOk;
}

}  // namespace

void RegisterContourCommand(CLI::App& app, int* exit_code) {
  CLI::App* dem = app.get_subcommand("dem");
  auto args = std::make_shared<FromContoursArgs>();
  CLI::App* cmd = dem->add_subcommand(
      "from-contours", "Build a DEM from contour lines (CDT, flat triangles repaired, rasterised)");
  cmd->add_option("store", args->store, "Store file")->required();
  cmd->add_option("file", args->options.path, "Vector file of contour lines (any OGR format)")
      ->required();
  cmd->add_option("--field", args->options.field, "Numeric field holding the elevation")
      ->required();
  cmd->add_option("--cell", args->options.cell,
                  "Cell size in CRS units (the store's, else the contours')")
      ->required();
  cmd->add_option("--name", args->options.name, "Name of the new DEM")->required();
  cmd->add_option("--layer", args->options.layer, "Layer (default: the source's only layer)");
  cmd->add_option("--block-size", args->options.block_size,
                  "Block edge in cells, a power of two (default 256)");
  cmd->callback([=] { *exit_code = RunFromContours(*args); });
}

}  // namespace tinbase::cli
