// Kernels: `locate` (triangle and z at a point), `neighbours` (a triangle's row and its three
// neighbours), `changes` (the change log since a transaction).
#include <iostream>
#include <nlohmann/json.hpp>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "db/change_log.h"
#include "db/point_locator.h"
#include "db/surface_store.h"

namespace tinbase::cli {

namespace {

struct SurfaceArgs : ReadArgs {
  std::string surface;
};

struct LocateArgs : SurfaceArgs {
  double x = 0;
  double y = 0;
};

nlohmann::json OptionalJson(const std::optional<int64_t>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}
nlohmann::json OptionalJson(const std::optional<std::string>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

int RunLocate(const LocateArgs& args) {
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  SurfaceStore surfaces(**store);
  auto surface = surfaces.Find(args.surface);
  if (!surface.ok()) return ReportError(surface.status());
  auto where = LocatePoint(**store, *surface, args.x, args.y);
  if (!where.ok()) return ReportError(where.status());
  if (args.json) {
    std::cout << nlohmann::json{{"surface", surface->name},
                                {"x", args.x},
                                {"y", args.y},
                                {"triangle", where->triangle},
                                {"z", where->z},
                                {"visible", where->visible},
                                {"tag", OptionalJson(where->tag)},
                                {"steps", where->steps}}
                     .dump()
              << "\n";
  } else {
    std::cout << "triangle " << where->triangle << ", z " << Num(where->z, 12) << ", "
              << (where->visible ? "visible" : "invisible")
              << (where->tag ? ", tag " + *where->tag : std::string()) << "\n";
  }
  return kExitOk;
}

struct NeighboursArgs : SurfaceArgs {
  int64_t id = 0;
};

int RunNeighbours(const NeighboursArgs& args) {
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  SurfaceStore surfaces(**store);
  auto surface = surfaces.Find(args.surface);
  if (!surface.ok()) return ReportError(surface.status());
  auto t = surfaces.Triangle(*surface, args.id);
  if (!t.ok()) return ReportError(t.status());
  std::optional<std::string> tag;
  if (t->tag) {
    auto value = surfaces.TagValue(*surface, *t->tag);
    if (!value.ok()) return ReportError(value.status());
    tag = *value;
  }
  if (args.json) {
    nlohmann::json j = {
        {"surface", surface->name},
        {"triangle", args.id},
        {"vertices", {t->v[0], t->v[1], t->v[2]}},
        {"neighbours", {OptionalJson(t->n[0]), OptionalJson(t->n[1]), OptionalJson(t->n[2])}},
        {"visible", t->visible},
        {"tag", OptionalJson(tag)},
        {"block", t->block}};
    std::cout << j.dump() << "\n";
  } else {
    std::cout << "triangle " << args.id << " (vertices " << t->v[0] << " " << t->v[1] << " "
              << t->v[2] << ")\n";
    for (int i = 0; i < 3; ++i)
      std::cout << "  opposite vertex " << t->v[i] << ": "
                << (t->n[i] ? "triangle " + std::to_string(*t->n[i]) : std::string("boundary"))
                << "\n";
  }
  return kExitOk;
}

struct ChangesArgs : ReadArgs {
  int64_t since = 0;
};

int RunChanges(const ChangesArgs& args) {
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  auto changes = ChangesSince(**store, args.since);
  if (!changes.ok()) return ReportError(changes.status());
  nlohmann::json j = nlohmann::json::array();
  for (const Change& c : *changes) {
    if (!args.json) {
      std::cout << "tx " << c.tx << " " << c.time << " " << c.action << ": -" << c.removed << " +"
                << c.added << " triangles in [" << Num(c.min_x) << ", " << Num(c.min_y) << ", "
                << Num(c.max_x) << ", " << Num(c.max_y) << "]\n";
      continue;
    }
    j.push_back({{"tx", c.tx},
                 {"time", c.time},
                 {"surface", OptionalJson(c.surface)},
                 {"feature", OptionalJson(c.feature)},
                 {"action", c.action},
                 {"removed", c.removed},
                 {"added", c.added},
                 {"bbox", {c.min_x, c.min_y, c.max_x, c.max_y}}});
  }
  if (args.json) std::cout << j.dump(2) << "\n";
  return kExitOk;
}

}  // namespace

void RegisterQueryCommands(CLI::App& app, int* exit_code) {
  auto locate_args = std::make_shared<LocateArgs>();
  CLI::App* locate = app.add_subcommand("locate", "The triangle holding a point and z there");
  locate->add_option("store", locate_args->store, "Store file")->required();
  locate->add_option("--surface", locate_args->surface, "Surface name")->required();
  locate->add_option("x", locate_args->x, "X in the store's CRS")->required();
  locate->add_option("y", locate_args->y, "Y in the store's CRS")->required();
  locate->add_flag("--json", locate_args->json, "Print JSON");
  locate->callback([=] { *exit_code = RunLocate(*locate_args); });

  auto nb_args = std::make_shared<NeighboursArgs>();
  CLI::App* nb = app.add_subcommand("neighbours", "A triangle's vertices and neighbours");
  nb->alias("neighbors");
  nb->add_option("store", nb_args->store, "Store file")->required();
  nb->add_option("--surface", nb_args->surface, "Surface name")->required();
  nb->add_option("id", nb_args->id, "Triangle id")->required();
  nb->add_flag("--json", nb_args->json, "Print JSON");
  nb->callback([=] { *exit_code = RunNeighbours(*nb_args); });

  auto ch_args = std::make_shared<ChangesArgs>();
  CLI::App* ch = app.add_subcommand("changes", "Write transactions after --since, oldest first");
  ch->add_option("store", ch_args->store, "Store file")->required();
  ch->add_option("--since", ch_args->since, "Transaction number (default 0: all)");
  ch->add_flag("--json", ch_args->json, "Print JSON");
  ch->callback([=] { *exit_code = RunChanges(*ch_args); });
}

}  // namespace tinbase::cli
