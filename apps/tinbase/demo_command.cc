// Kernel: `demo`, the whole path once on the bundled Hamersley data (GSWA, Western Australia):
// a new store, the DEM imported, a terrain TIN built, a geological unit draped on it, queries, an
// export and the integrity check, each step timed. It calls the same library functions as the
// individual commands.
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "core/export/tin_export.h"
#include "db/change_log.h"
#include "db/dem_store.h"
#include "db/integrity_check.h"
#include "db/point_locator.h"
#include "db/polygon_editor.h"
#include "db/surface_builder.h"
#include "db/surface_store.h"

namespace tinbase::cli {

namespace {

struct DemoArgs {
  std::string workdir = "tinbase-demo";
  std::string data = TINBASE_DEMO_DATA_DIR;
  double tolerance = 5;
};

// Runs one step, prints its line with the time it took, and stops the demo on error.
class DemoSteps {
 public:
  template <typename Fn>
  bool Run(const std::string& name, Fn&& fn) {
    Stopwatch watch;
    Result<std::string> outcome = fn();
    const double seconds = watch.Seconds();
    if (!outcome.ok()) {
      std::cerr << "tinbase: demo step '" << name << "' failed: " << outcome.status().message()
                << "\n";
      return false;
    }
    total_ += seconds;
    std::cout << "  " << std::left << std::setw(16) << name << std::right << std::setw(9)
              << std::fixed << std::setprecision(3) << seconds << " s  " << *outcome << "\n";
    return true;
  }
  double total() const { return total_; }

 private:
  double total_ = 0;
};

void RemoveStore(const std::string& path) {
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
}

int RunDemo(const DemoArgs& args) {
  std::filesystem::create_directories(args.workdir);
  const std::string path = args.workdir + "/demo.tinbase";
  RemoveStore(path);
  const std::string dem_file = args.data + "/geology/hamersley/dtm_rp.tif";
  const std::string geology = args.data + "/geology/hamersley/geology.geojson";
  std::cout << "tinbase demo: Hamersley, Western Australia (GSWA DEM and geology)\n";

  std::unique_ptr<Store> store;
  DemStore* dems = nullptr;
  std::unique_ptr<DemStore> dem_store;
  SurfaceInfo surface;
  int64_t located = 0;
  DemoSteps steps;
  const bool ok = steps.Run("create store", [&]() -> Result<std::string> {
    TB_ASSIGN_OR_RETURN(store, Store::Create(path, ""));
    dem_store = std::make_unique<DemStore>(*store);
    dems = dem_store.get();
    return path;
  }) && steps.Run("import DEM", [&]() -> Result<std::string> {
    TB_ASSIGN_OR_RETURN(auto r, dems->Import({dem_file}, {}));
    return "dtm_rp.tif: " + std::to_string(r.dem.geometry.width) + " x " +
           std::to_string(r.dem.geometry.height) + " cells, " + std::to_string(r.blocks_written) +
           " blocks, " + Num(r.bytes_stored / 1024.0, 4) + " KiB";
  }) && steps.Run("build TIN", [&]() -> Result<std::string> {
    SurfaceBuildOptions o;
    o.surface = "terrain";
    o.greedy.tolerance = args.tolerance;
    TB_ASSIGN_OR_RETURN(auto r, BuildSurfaceFromDem(*store, o));
    surface = r.surface;
    return "greedy to " + Num(args.tolerance) + " m: " + std::to_string(r.vertices) +
           " vertices, " + std::to_string(r.triangles) + " triangles, max error " +
           Num(r.quality.max_error, 3) + " m";
  }) && steps.Run("add polygons", [&]() -> Result<std::string> {
    PolygonAddOptions o;
    o.surface = "terrain";
    o.file = geology;
    o.mode = FeatureMode::kFill;
    o.tag_field = "unitname";
    TB_ASSIGN_OR_RETURN(auto r, AddPolygons(*store, o));
    return std::to_string(r.features) + " geological units (fill, tag = unitname), " +
           std::to_string(r.ring_vertices) + " draped ring vertices, " + std::to_string(r.added) +
           " triangles";
  }) && steps.Run("locate", [&]() -> Result<std::string> {
    SurfaceStore surfaces(*store);
    TB_ASSIGN_OR_RETURN(surface, surfaces.Find("terrain"));
    TB_ASSIGN_OR_RETURN(DemInfo dem, dems->FindById(*surface.dem));
    const double x = (dem.geometry.MinX() + dem.geometry.MaxX()) / 2;
    const double y = (dem.geometry.MinY() + dem.geometry.MaxY()) / 2;
    TB_ASSIGN_OR_RETURN(Location where, LocatePoint(*store, surface, x, y));
    TB_ASSIGN_OR_RETURN(double dem_z, dems->Sample(dem, x, y));
    located = where.triangle;
    return "centre (" + Num(x) + ", " + Num(y) + "): triangle " + std::to_string(where.triangle) +
           ", z " + Num(where.z, 6) + " (DEM " + Num(dem_z, 6) + "), " +
           where.tag.value_or("untagged") + ", " + std::to_string(where.steps) + " steps";
  }) && steps.Run("neighbours", [&]() -> Result<std::string> {
    SurfaceStore surfaces(*store);
    TB_ASSIGN_OR_RETURN(TriangleRow t, surfaces.Triangle(surface, located));
    std::string out = "triangle " + std::to_string(located) + ":";
    for (const auto& n : t.n) out += " " + (n ? std::to_string(*n) : std::string("-"));
    return out;
  }) && steps.Run("changes", [&]() -> Result<std::string> {
    TB_ASSIGN_OR_RETURN(auto changes, ChangesSince(*store, 0));
    std::string out = std::to_string(changes.size()) + " transactions:";
    for (const Change& c : changes) out += " [" + std::to_string(c.tx) + " " + c.action + "]";
    return out;
  }) && steps.Run("export", [&]() -> Result<std::string> {
    SurfaceStore surfaces(*store);
    TB_ASSIGN_OR_RETURN(LoadedSurface loaded, surfaces.Load(surface));
    TB_ASSIGN_OR_RETURN(auto crs, store->GetCrs());
    std::string out;
    for (ExportFormat format : {ExportFormat::kObj, ExportFormat::kGeoJson}) {
      ExportOptions o;
      o.format = format;
      o.visible_only = true;
      o.triangle_ids = loaded.triangle_ids;
      const std::string file =
          args.workdir + (format == ExportFormat::kObj ? "/terrain.obj" : "/terrain.geojson");
      TB_ASSIGN_OR_RETURN(auto r, ExportTin(loaded.tin, crs ? &*crs : nullptr, file, o));
      out += (out.empty() ? "" : ", ") + file + " (" + std::to_string(r.triangles) + ")";
    }
    return out;
  }) && steps.Run("check", [&]() -> Result<std::string> {
    TB_ASSIGN_OR_RETURN(auto problems, CheckStore(*store, {.surface = {}, .full = true}));
    if (!problems.empty()) return Status::Corruption(problems.front().message);
    return std::string("every invariant holds");
  });
  if (!ok) return kExitFailure;
  std::cout << "  total           " << std::fixed << std::setprecision(3) << std::setw(9)
            << steps.total() << " s\n"
            << "store: " << path << "  (try: tinbase info " << path << ")\n";
  return kExitOk;
}

}  // namespace

void RegisterDemoCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<DemoArgs>();
  CLI::App* demo = app.add_subcommand("demo", "Run the whole pipeline on the bundled demo data");
  demo->add_option("--workdir", args->workdir, "Where the store and exports go");
  demo->add_option("--data", args->data, "The tests/data folder of a tinbase checkout");
  demo->add_option("--tolerance", args->tolerance, "TIN tolerance in metres (default 5)");
  demo->callback([=] { *exit_code = RunDemo(*args); });
}

}  // namespace tinbase::cli
