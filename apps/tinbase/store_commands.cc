// Kernels: `init` (create a store), `info` (what a store holds), `check` (the integrity checker).
#include <iostream>
#include <nlohmann/json.hpp>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "db/dem_store.h"
#include "db/integrity_check.h"
#include "db/integrity_check_json.h"
#include "db/store.h"
#include "db/surface_json.h"
#include "db/surface_store.h"

namespace tinbase::cli {

namespace {

struct InitArgs {
  std::string store;
  std::string crs;
};

int RunInit(const InitArgs& args) {
  auto store = Store::Create(args.store, args.crs);
  if (!store.ok()) return ReportError(store.status());
  auto crs = (*store)->GetCrs();
  std::cout << "created " << args.store << " (schema version " << (*store)->SchemaVersion()
            << ", CRS "
            << (crs.ok() && crs->has_value() ? (*crs)->Label() : "set by the first import")
            << ")\n";
  return kExitOk;
}

Result<nlohmann::json> DescribeStore(Store& store) {
  nlohmann::json out;
  out["store"] = store.path();
  out["schema_version"] = store.SchemaVersion();
  TB_ASSIGN_OR_RETURN(auto crs, store.GetCrs());
  out["crs"] = crs ? nlohmann::json(crs->Label()) : nlohmann::json(nullptr);
  DemStore dems(store);
  TB_ASSIGN_OR_RETURN(auto dem_list, dems.List());
  out["dems"] = nlohmann::json::array();
  for (const DemInfo& d : dem_list) {
    TB_ASSIGN_OR_RETURN(std::vector<DemLevelStats> stats, dems.LevelStats(d));
    const int64_t blocks = stats[0].blocks;
    out["dems"].push_back(
        {{"name", d.name},
         {"width", d.geometry.width},
         {"height", d.geometry.height},
         {"cell_size", {d.geometry.cell_x, -d.geometry.cell_y}},
         {"bbox", {d.geometry.MinX(), d.geometry.MinY(), d.geometry.MaxX(), d.geometry.MaxY()}},
         {"block_size", d.block_size},
         {"blocks", blocks},
         {"levels", d.levels}});
  }
  SurfaceStore surfaces(store);
  TB_ASSIGN_OR_RETURN(auto surface_list, surfaces.List());
  out["surfaces"] = nlohmann::json::array();
  for (const SurfaceInfo& s : surface_list) {
    TB_ASSIGN_OR_RETURN(SurfaceCounts c, surfaces.Count(s));
    out["surfaces"].push_back(SurfaceSummaryJson(s, c));
  }
  return out;
}

void PrintStore(const nlohmann::json& j) {
  std::cout << "store " << j["store"].get<std::string>() << " (schema version "
            << j["schema_version"] << ", CRS "
            << (j["crs"].is_null() ? "not set" : j["crs"].get<std::string>()) << ")\n";
  std::cout << "DEMs: " << j["dems"].size() << "\n";
  for (const auto& d : j["dems"])
    std::cout << "  " << d["name"].get<std::string>() << ": " << d["width"] << " x " << d["height"]
              << " cells of " << d["cell_size"][0] << " x " << d["cell_size"][1] << ", "
              << d["blocks"] << " blocks of " << d["block_size"] << ", " << d["levels"]
              << " level(s)\n";
  std::cout << "surfaces: " << j["surfaces"].size() << "\n";
  for (const auto& s : j["surfaces"])
    std::cout << "  " << s["name"].get<std::string>() << " (" << s["kind"].get<std::string>()
              << ", " << s["method"].get<std::string>() << "): " << s["vertices"] << " vertices, "
              << s["triangles"] << " triangles (" << s["visible_triangles"] << " visible), "
              << s["constraints"] << " constraints, " << s["features"] << " features\n";
}

struct CheckArgs {
  std::string store;
  std::string surface;
  bool json = false;
  bool full = false;
};

int RunCheck(const CheckArgs& args) {
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  CheckOptions options;
  if (!args.surface.empty()) options.surface = args.surface;
  options.full = args.full;
  auto problems = CheckStore(**store, options);
  if (!problems.ok()) return ReportError(problems.status());
  if (args.json) {
    std::cout << CheckJson(*problems).dump(2) << "\n";
  } else if (problems->empty()) {
    std::cout << "ok: " << args.store << " keeps every checked invariant"
              << (args.full ? " (full: 1-9)" : " (1-5, 8)") << "\n";
  } else {
    std::cerr << "tinbase: " << problems->front().message << " [" << problems->front().code << "]";
    if (problems->size() > 1) std::cerr << " (and " << problems->size() - 1 << " more)";
    std::cerr << "\n";
  }
  return problems->empty() ? kExitOk : kExitFailure;
}

}  // namespace

void RegisterStoreCommands(CLI::App& app, int* exit_code) {
  auto init_args = std::make_shared<InitArgs>();
  CLI::App* init = app.add_subcommand("init", "Create a new, empty store");
  init->add_option("store", init_args->store, "Path of the store file to create")->required();
  init->add_option("--crs", init_args->crs,
                   "The store's CRS (e.g. EPSG:32632); default: set by the first DEM");
  init->callback([=] { *exit_code = RunInit(*init_args); });

  auto info_args = std::make_shared<ReadArgs>();
  CLI::App* info = app.add_subcommand("info", "List the store's DEMs and surfaces with counts");
  info->add_option("store", info_args->store, "Store file")->required();
  info->add_flag("--json", info_args->json, "Print JSON");
  info->callback([=] {
    auto store = Store::Open(info_args->store, Store::Access::kReadOnly);
    if (!store.ok()) {
      *exit_code = ReportError(store.status());
      return;
    }
    auto j = DescribeStore(**store);
    if (!j.ok()) {
      *exit_code = ReportError(j.status());
      return;
    }
    if (info_args->json)
      std::cout << j->dump(2) << "\n";
    else
      PrintStore(*j);
    *exit_code = kExitOk;
  });

  auto check_args = std::make_shared<CheckArgs>();
  CLI::App* check = app.add_subcommand(
      "check", "Verify the store's invariants (docs/design.md, Invariants 1-5, 8; --full: all 8)");
  check->add_option("store", check_args->store, "Store file")->required();
  check->add_option("--surface", check_args->surface, "Check only this surface");
  check->add_flag("--json", check_args->json, "Print every problem as JSON");
  check->add_flag("--full", check_args->full,
                  "Also recompute visibility and tags from the features (6) and verify the "
                  "tolerance against the DEM (7)");
  check->callback([=] { *exit_code = RunCheck(*check_args); });
}

}  // namespace tinbase::cli
