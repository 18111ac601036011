// Kernels: `revert` (undo a committed edit transaction by its inverse, as a new transaction) and
// `history` (the versions of one feature). The library does the work (db/history/revert.h,
// db/history/feature_versions.h); these parse arguments and print.
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "db/history/feature_versions.h"
#include "db/history/revert.h"
#include "db/tiles/tile_pyramid.h"

namespace tinbase::cli {

namespace {

struct RevertArgs : ReadArgs {
  int64_t tx = 0;
  bool cascade = false;
  bool update_tiles = false;
};

// Tiles rewritten or deleted by one pyramid update: surface name, rewritten, deleted.
struct TilesUpdated {
  std::string surface;
  int64_t rewritten = 0;
  int64_t deleted = 0;
};

// --update-tiles: every pyramid brought up to date inside the revert's transaction, so the revert
// and its tiles commit together (a failure rolls the revert back).
BeforeCommit UpdateTilesWithRevert(std::vector<TilesUpdated>* out) {
  return [out](Store& store, int64_t /*tx*/) -> Status {
    auto updated = UpdateAllTilePyramids(store);
    if (!updated.ok()) return updated.status().WithContext("updating the tiles of the revert");
    for (const auto& [surface, r] : *updated)
      out->push_back({surface.name, r.tiles_rewritten, r.tiles_deleted});
    return Status::Ok();
  };
}

std::string JoinIds(const std::vector<int64_t>& ids) {
  std::string out;
  for (int64_t id : ids) out += (out.empty() ? "" : ", ") + std::to_string(id);
  return out.empty() ? "none" : out;
}

int RunRevert(const RevertArgs& args) {
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  Stopwatch watch;
  std::vector<TilesUpdated> tiles;
  RevertOptions options;
  options.cascade = args.cascade;
  if (args.update_tiles) options.before_commit = UpdateTilesWithRevert(&tiles);
  auto report = RevertTransaction(**store, args.tx, options);
  if (!report.ok()) return ReportError(report.status());
  if (args.json) {
    nlohmann::json j = {{"reverted", report->reverted},
                        {"transactions", report->transactions},
                        {"removed_features", report->removed_features},
                        {"restored_features", report->restored_features},
                        {"removed", report->removed},
                        {"added", report->added},
                        {"exact", report->exact}};
    if (!report->exact) j["not_exact"] = report->not_exact;
    if (args.update_tiles) {
      j["tiles"] = nlohmann::json::array();
      for (const TilesUpdated& t : tiles)
        j["tiles"].push_back(
            {{"surface", t.surface}, {"rewritten", t.rewritten}, {"deleted", t.deleted}});
    }
    std::cout << j.dump(2) << "\n";
    return kExitOk;
  }
  std::cout << "reverted transaction(s) " << JoinIds(report->reverted) << " in transaction(s) "
            << JoinIds(report->transactions)
            << ": features removed " + JoinIds(report->removed_features) + ", restored " +
                   JoinIds(report->restored_features) + "; "
            << report->removed << " triangles replaced by " << report->added << " in "
            << Num(watch.Seconds(), 3) << " s\n";
  if (report->exact) {
    std::cout << "the mesh is back exactly as it was (from the edits' mesh images)\n";
  } else {
    std::cout << "not the exact mesh: " << report->not_exact
              << "; the region was re-triangulated and refined to the tolerance instead\n";
  }
  for (const TilesUpdated& t : tiles)
    std::cout << "tiles of '" << t.surface << "': " << t.rewritten << " rewritten, " << t.deleted
              << " deleted\n";
  return kExitOk;
}

struct HistoryArgs : ReadArgs {
  int64_t feature = 0;
};

// What version `k` of `versions` did to the feature.
std::string StateOf(const std::vector<FeatureVersion>& versions, size_t k) {
  if (!versions[k].present) return "removed";
  if (k == 0) return "added";
  return versions[k - 1].present ? "changed" : "restored";
}

int RunHistory(const HistoryArgs& args) {
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  auto versions = VersionsOfFeature(**store, args.feature);
  if (!versions.ok()) return ReportError(versions.status());
  if (versions->empty())
    return ReportError(Status::NotFound(std::string("feature ") + std::to_string(args.feature) +
                                        " has no history"));
  nlohmann::json j = nlohmann::json::array();
  for (size_t k = 0; k < versions->size(); ++k) {
    const FeatureVersion& v = (*versions)[k];
    // The other features of the same transaction: an update's old or new feature.
    auto touched = FeaturesTouchedBy(**store, v.tx);
    if (!touched.ok()) return ReportError(touched.status());
    std::erase(*touched, v.feature);
    const std::string state = StateOf(*versions, k);
    if (!args.json) {
      std::cout << "tx " << v.tx << " " << v.time << " " << v.action << ": " << state << ", mode "
                << v.mode << (v.tag ? ", tag " + *v.tag : "")
                << (v.level ? ", level " + Num(*v.level) : "")
                << (touched->empty() ? "" : " (with feature(s) " + JoinIds(*touched) + ")") << "\n";
      continue;
    }
    j.push_back({{"tx", v.tx},
                 {"time", v.time},
                 {"action", v.action},
                 {"state", state},
                 {"mode", v.mode},
                 {"tag", v.tag ? nlohmann::json(*v.tag) : nlohmann::json(nullptr)},
                 {"level", v.level ? nlohmann::json(*v.level) : nlohmann::json(nullptr)},
                 {"with", *touched}});
  }
  if (args.json)
    std::cout << nlohmann::json({{"feature", args.feature}, {"versions", j}}).dump(2) << "\n";
  return kExitOk;
}

}  // namespace

void RegisterHistoryCommands(CLI::App& app, int* exit_code) {
  auto revert = std::make_shared<RevertArgs>();
  CLI::App* r = app.add_subcommand(
      "revert", "Undo a committed edit transaction by its inverse, as a new transaction");
  r->add_option("store", revert->store, "Store file")->required();
  r->add_option("tx", revert->tx, "The transaction to undo (see `changes`)")->required();
  r->add_flag("--cascade", revert->cascade,
              "Also undo the later edits of the same features (else they make it fail)");
  r->add_flag("--update-tiles", revert->update_tiles,
              "Bring every tile pyramid up to date in the revert's own transaction");
  r->add_flag("--json", revert->json, "Print JSON");
  r->callback([=] { *exit_code = RunRevert(*revert); });

  auto history = std::make_shared<HistoryArgs>();
  CLI::App* h = app.add_subcommand("history", "The versions of one feature, oldest first");
  h->add_option("store", history->store, "Store file")->required();
  h->add_option("--feature", history->feature, "Feature id")->required();
  h->add_flag("--json", history->json, "Print JSON");
  h->callback([=] { *exit_code = RunHistory(*history); });
}

}  // namespace tinbase::cli
