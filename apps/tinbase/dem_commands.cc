// Kernels: `dem import` (rasters into the blocked DEM store) and `dem sample` (bilinear z).
#include <iostream>

#include <nlohmann/json.hpp>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "db/dem_store.h"
#include "db/surface_builder.h"

namespace tinbase::cli {

namespace {

struct ImportArgs {
  std::string store;
  std::vector<std::string> files;
  std::string name;
  int block_size = 256;
};

int RunImport(const ImportArgs& args) {
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  DemStore dems(**store);
  DemImportOptions options;
  options.name = args.name;
  options.block_size = args.block_size;
  Stopwatch watch;
  auto report = dems.Import(args.files, options);
  if (!report.ok()) return ReportError(report.status());
  const DemInfo& d = report->dem;
  std::cout << "imported " << args.files.size() << " file(s) into DEM '" << d.name << "': "
            << d.geometry.width << " x " << d.geometry.height << " cells, "
            << report->blocks_written << " blocks, "
            << Num(report->bytes_stored / 1048576.0, 3) << " MiB stored"
            << (report->warped ? ", warped onto the store's CRS" : "") << " in "
            << Num(watch.Seconds(), 3) << " s\n";
  return kExitOk;
}

struct SampleArgs : ReadArgs {
  double x = 0;
  double y = 0;
  std::string dem;
};

int RunSample(const SampleArgs& args) {
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  DemStore dems(**store);
  auto dem = ResolveDem(dems, args.dem);
  if (!dem.ok()) return ReportError(dem.status());
  auto z = dems.Sample(*dem, args.x, args.y);
  if (!z.ok()) return ReportError(z.status());
  if (args.json) {
    std::cout << nlohmann::json{{"dem", dem->name}, {"x", args.x}, {"y", args.y}, {"z", *z}}.dump()
              << "\n";
  } else {
    std::cout << Num(*z, 12) << "\n";
  }
  return kExitOk;
}

}  // namespace

void RegisterDemCommands(CLI::App& app, int* exit_code) {
  CLI::App* dem = app.add_subcommand("dem", "The blocked DEM database");
  dem->require_subcommand(1);

  auto import_args = std::make_shared<ImportArgs>();
  CLI::App* import = dem->add_subcommand("import", "Import GDAL rasters (GeoTIFF, .hgt, ...) as a DEM");
  import->add_option("store", import_args->store, "Store file")->required();
  import->add_option("files", import_args->files, "Raster files")->required();
  import->add_option("--name", import_args->name, "DEM name (default: the first file's stem)");
  import->add_option("--block-size", import_args->block_size,
                     "Block edge in cells, a power of two (default 256)");
  import->callback([=] { *exit_code = RunImport(*import_args); });

  auto sample_args = std::make_shared<SampleArgs>();
  CLI::App* sample = dem->add_subcommand("sample", "Bilinear elevation at a point (store CRS)");
  sample->add_option("store", sample_args->store, "Store file")->required();
  sample->add_option("x", sample_args->x, "X in the store's CRS")->required();
  sample->add_option("y", sample_args->y, "Y in the store's CRS")->required();
  sample->add_option("--dem", sample_args->dem, "DEM name (default: the only DEM)");
  sample->add_flag("--json", sample_args->json, "Print JSON");
  sample->callback([=] { *exit_code = RunSample(*sample_args); });
}

}  // namespace tinbase::cli
