// Kernels: `locate` (triangle and z at a point, or at every point of a file, streamed), `star`
// (the triangles and vertices around a vertex), `triangles` (those of a window or a feature),
// `neighbours` (a triangle's neighbours and the edges they share), `profile` (a section along a
// polyline, CSV/JSON and a PNG plot), `changes` (the change log since a transaction).
#include <algorithm>
#include <charconv>
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "core/base/output_file.h"
#include "core/query/point_input.h"
#include "core/query/profile_plot.h"
#include "db/change_log.h"
#include "db/point_locator.h"
#include "db/query/bulk_locate.h"
#include "db/query/profile.h"
#include "db/query/profile_json.h"
#include "db/query/surface_selection.h"
#include "db/query/topology.h"
#include "db/surface_store.h"

namespace tinbase::cli {

namespace {

struct SurfaceArgs : ReadArgs {
  std::string surface;
};

nlohmann::json OptionalJson(const std::optional<int64_t>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}
nlohmann::json OptionalJson(const std::optional<std::string>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

// The shortest text that reads back as the same double, for CSV that scripts read.
std::string Exact(double v) {
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  return std::string(buf, end);
}

// A CSV field: quoted, with quotes doubled, when it holds a comma, quote or line break.
std::string CsvField(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

// The store, opened read-only, and the surface the command names.
struct OpenSurface {
  std::unique_ptr<Store> store;
  SurfaceInfo surface;
};

Result<OpenSurface> Open(const SurfaceArgs& args) {
  OpenSurface open;
  TB_ASSIGN_OR_RETURN(open.store, Store::Open(args.store, Store::Access::kReadOnly));
  TB_ASSIGN_OR_RETURN(open.surface, SurfaceStore(*open.store).Find(args.surface));
  return open;
}

// ---- locate

struct LocateArgs : SurfaceArgs {
  std::optional<double> x;
  std::optional<double> y;
  std::string points;  // file or "-"; empty: locate (x, y)
};

int RunLocateOne(OpenSurface& open, double x, double y, bool json) {
  auto where = LocatePoint(*open.store, open.surface, x, y);
  if (!where.ok()) return ReportError(where.status());
  if (json) {
    std::cout << nlohmann::json{{"surface", open.surface.name},
                                {"x", x},
                                {"y", y},
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

// One output line per point: a CSV row or a JSON object; a point outside the surface has no
// triangle, z, visibility or tag.
void PrintLocated(const Point2& p, const Location* where, bool json) {
  if (json) {
    nlohmann::json j = {{"x", p.x},     {"y", p.y},           {"triangle", nullptr},
                        {"z", nullptr}, {"visible", nullptr}, {"tag", nullptr}};
    if (where != nullptr) {
      j["triangle"] = where->triangle;
      j["z"] = where->z;
      j["visible"] = where->visible;
      j["tag"] = OptionalJson(where->tag);
    }
    std::cout << j.dump() << '\n';
    return;
  }
  std::cout << Exact(p.x) << ',' << Exact(p.y) << ',';
  if (where != nullptr)
    std::cout << where->triangle << ',' << Exact(where->z) << ','
              << (where->visible ? "true" : "false") << ',' << CsvField(where->tag.value_or(""));
  else
    std::cout << ",,,";
  std::cout << '\n';
}

int RunLocatePoints(OpenSurface& open, const std::string& file, bool json) {
  auto crs = open.store->GetCrs();
  if (!crs.ok()) return ReportError(crs.status());
  // Every point is read and checked before the first answer is printed: a bad line stops the
  // command with no output at all.
  auto points = ReadPoints(file, *crs);
  if (!points.ok()) return ReportError(points.status());
  if (!json) std::cout << "x,y,triangle,z,visible,tag\n";
  Status s = LocatePoints(*open.store, open.surface, *points,
                          [&](size_t, const Point2& p, const Location* where) {
                            PrintLocated(p, where, json);
                            return Status::Ok();
                          });
  std::cout.flush();
  if (!s.ok()) return ReportError(s);
  return kExitOk;
}

int RunLocate(const LocateArgs& args) {
  if (!args.points.empty() && (args.x || args.y))
    return ReportError(Status::InvalidArgument("give either x y or --points, not both"));
  if (args.points.empty() && !(args.x && args.y))
    return ReportError(Status::InvalidArgument("give x y, or --points FILE (- for stdin)"));
  auto open = Open(args);
  if (!open.ok()) return ReportError(open.status());
  if (!args.points.empty()) return RunLocatePoints(*open, args.points, args.json);
  return RunLocateOne(*open, *args.x, *args.y, args.json);
}

// ---- star

struct StarArgs : SurfaceArgs {
  int64_t vertex = 0;
};

int RunStar(const StarArgs& args) {
  auto open = Open(args);
  if (!open.ok()) return ReportError(open.status());
  auto star = StarOf(*open->store, open->surface, args.vertex);
  if (!star.ok()) return ReportError(star.status());
  if (args.json) {
    std::cout << nlohmann::json{{"surface", open->surface.name},
                                {"vertex", star->vertex},
                                {"x", star->row.x},
                                {"y", star->row.y},
                                {"z", star->row.z},
                                {"kind", VertexKindName(star->row.kind)},
                                {"boundary", star->boundary},
                                {"triangles", star->triangles},
                                {"links", star->links}}
                     .dump()
              << "\n";
    return kExitOk;
  }
  std::cout << "vertex " << star->vertex << " (" << Num(star->row.x, 12) << ", "
            << Num(star->row.y, 12) << ", " << Num(star->row.z, 12) << "), "
            << (star->boundary ? "on the boundary" : "inside") << "\n  triangles:";
  for (int64_t t : star->triangles) std::cout << " " << t;
  std::cout << "\n  linked vertices:";
  for (int64_t v : star->links) std::cout << " " << v;
  std::cout << "\n";
  return kExitOk;
}

// ---- triangles

struct TrianglesArgs : SurfaceArgs {
  std::string bbox;
  int64_t feature = 0;
  bool visible_only = false;
  std::string tag;
};

Result<SurfaceFilter> FilterOf(const TrianglesArgs& args) {
  if (args.bbox.empty() && args.feature == 0)
    return Status::InvalidArgument("give --bbox minx,miny,maxx,maxy or --feature ID");
  SurfaceFilter filter;
  if (!args.bbox.empty()) {
    Result<Box> box = ParseBbox(args.bbox);
    if (!box.ok()) return box.status().WithContext("--bbox");
    filter.bbox = *box;
  }
  filter.feature = args.feature;
  filter.visible_only = args.visible_only;
  if (!args.tag.empty()) filter.tag = args.tag;
  return filter;
}

nlohmann::json TriangleJson(const LoadedSurface& s, size_t t) {
  const TinTriangle& tri = s.tin.triangles[t];
  nlohmann::json vertices = nlohmann::json::array(), corners = nlohmann::json::array(),
                 neighbours = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) {
    const TinVertex& v = s.tin.vertices[tri.v[i]];
    vertices.push_back(s.vertex_ids[tri.v[i]]);
    corners.push_back({v.x, v.y, v.z});
    neighbours.push_back(tri.n[i] == kNoNeighbour
                             ? nlohmann::json(nullptr)
                             : nlohmann::json(s.triangle_ids[static_cast<size_t>(tri.n[i])]));
  }
  return {{"id", s.triangle_ids[t]},
          {"vertices", vertices},
          {"corners", corners},
          {"neighbours", neighbours},
          {"visible", tri.visible},
          {"tag", tri.tag == kNoTag ? nlohmann::json(nullptr)
                                    : nlohmann::json(s.tin.tags[static_cast<size_t>(tri.tag)])}};
}

int RunTriangles(const TrianglesArgs& args) {
  auto filter = FilterOf(args);
  if (!filter.ok()) return ReportError(filter.status());
  auto open = Open(args);
  if (!open.ok()) return ReportError(open.status());
  auto selected = SelectSurface(*open->store, open->surface, *filter);
  if (!selected.ok()) return ReportError(selected.status());
  const LoadedSurface& s = *selected;
  if (args.json) {
    nlohmann::json triangles = nlohmann::json::array();
    for (size_t t = 0; t < s.tin.triangles.size(); ++t) triangles.push_back(TriangleJson(s, t));
    std::cout << nlohmann::json{{"surface", open->surface.name},
                                {"filter", filter->Describe()},
                                {"count", s.tin.triangles.size()},
                                {"triangles", triangles}}
                     .dump()
              << "\n";
    return kExitOk;
  }
  std::cout << s.tin.triangles.size() << " triangles of surface '" << open->surface.name << "' for "
            << filter->Describe() << "\n";
  for (size_t t = 0; t < s.tin.triangles.size(); ++t) {
    const TinTriangle& tri = s.tin.triangles[t];
    std::cout << "triangle " << s.triangle_ids[t] << ": vertices " << s.vertex_ids[tri.v[0]] << " "
              << s.vertex_ids[tri.v[1]] << " " << s.vertex_ids[tri.v[2]]
              << (tri.visible ? "" : ", invisible")
              << (tri.tag == kNoTag ? std::string() : ", tag " + s.tin.tags[tri.tag]) << "\n";
  }
  return kExitOk;
}

// ---- neighbours

struct NeighboursArgs : SurfaceArgs {
  int64_t id = 0;
};

nlohmann::json VertexJson(const VertexRow& v) { return {v.x, v.y, v.z}; }

int RunNeighbours(const NeighboursArgs& args) {
  auto open = Open(args);
  if (!open.ok()) return ReportError(open.status());
  auto nb = NeighboursOf(*open->store, open->surface, args.id);
  if (!nb.ok()) return ReportError(nb.status());
  const TriangleRow& t = nb->row;
  if (args.json) {
    nlohmann::json edges = nlohmann::json::array();
    for (const SharedEdge& e : nb->edges)
      edges.push_back({{"neighbour", OptionalJson(e.neighbour)},
                       {"vertices", e.vertices},
                       {"from", VertexJson(e.ends[0])},
                       {"to", VertexJson(e.ends[1])},
                       {"constrained", e.constrained}});
    nlohmann::json j = {
        {"surface", open->surface.name},
        {"triangle", args.id},
        {"vertices", {t.v[0], t.v[1], t.v[2]}},
        {"neighbours", {OptionalJson(t.n[0]), OptionalJson(t.n[1]), OptionalJson(t.n[2])}},
        {"edges", edges},
        {"visible", t.visible},
        {"tag", OptionalJson(nb->tag)},
        {"block", t.block}};
    std::cout << j.dump() << "\n";
    return kExitOk;
  }
  std::cout << "triangle " << args.id << " (vertices " << t.v[0] << " " << t.v[1] << " " << t.v[2]
            << ")\n";
  for (int i = 0; i < 3; ++i) {
    const SharedEdge& e = nb->edges[i];
    std::cout << "  opposite vertex " << t.v[i] << ": "
              << (e.neighbour ? "triangle " + std::to_string(*e.neighbour)
                              : std::string("boundary"))
              << ", edge " << e.vertices[0] << "-" << e.vertices[1]
              << (e.constrained ? ", constrained" : "") << "\n";
  }
  return kExitOk;
}

// ---- profile

struct ProfileArgs : SurfaceArgs {
  std::string line;
  std::string line_file;
  std::string plot;
  int width = 1000;
  int height = 400;
};

Result<std::vector<Point2>> LineOf(const ProfileArgs& args, const std::optional<Crs>& crs) {
  if (args.line.empty() == args.line_file.empty())
    return Status::InvalidArgument(
        "give the profile line as --line \"x,y x,y ...\" or "
        "--line-file FILE, one of them");
  if (!args.line.empty()) return ParsePointList(args.line, "--line");
  return ReadLine(args.line_file, crs);
}

// Each tag's colour: its place among the profile's tags in alphabetical order.
std::vector<ProfilePlotStretch> PlotStretches(const SurfaceProfile& profile) {
  std::set<std::string> tags;
  for (const ProfileStretch& s : profile.stretches)
    if (s.tag) tags.insert(*s.tag);
  std::vector<ProfilePlotStretch> out;
  for (const ProfileStretch& s : profile.stretches) {
    const int series =
        s.tag ? static_cast<int>(std::distance(tags.begin(), tags.find(*s.tag))) : -1;
    out.push_back({series, s.visible});
  }
  return out;
}

void PrintProfile(const SurfaceProfile& p, const std::string& surface, bool json) {
  if (json) {
    std::cout << ProfileJson(p, surface).dump() << "\n";
    return;
  }
  std::cout << "distance,x,y,z,kind,triangle,visible,tag\n";
  for (size_t i = 0; i < p.stations.size(); ++i) {
    const Station& s = p.stations[i];
    std::cout << Exact(s.distance) << ',' << Exact(s.x) << ',' << Exact(s.y) << ',' << Exact(s.z)
              << ',' << StationKindName(s.kind) << ',';
    if (i < p.stretches.size()) {
      const ProfileStretch& r = p.stretches[i];
      std::cout << r.triangle << ',' << (r.visible ? "true" : "false") << ','
                << CsvField(r.tag.value_or(""));
    } else {
      std::cout << ",,";
    }
    std::cout << '\n';
  }
}

int RunProfile(const ProfileArgs& args) {
  auto open = Open(args);
  if (!open.ok()) return ReportError(open.status());
  auto crs = open->store->GetCrs();
  if (!crs.ok()) return ReportError(crs.status());
  auto line = LineOf(args, *crs);
  if (!line.ok()) return ReportError(line.status());
  // The plot's path is checked before the profile is computed, and the file appears only once
  // it is complete.
  std::optional<OutputFile> plot;
  if (!args.plot.empty()) {
    auto file = OutputFile::Create(args.plot);
    if (!file.ok()) return ReportError(file.status().WithContext("--plot"));
    plot.emplace(std::move(*file));
  }
  auto profile = ProfileAlong(*open->store, open->surface, *line);
  if (!profile.ok()) return ReportError(profile.status());
  if (plot) {
    ProfilePlotOptions options;
    options.width = args.width;
    options.height = args.height;
    Status s =
        WriteProfilePlot(profile->stations, PlotStretches(*profile), plot->temp_path(), options);
    if (s.ok()) s = plot->Commit();
    if (!s.ok()) return ReportError(s);
  }
  PrintProfile(*profile, open->surface.name, args.json);
  return kExitOk;
}

// ---- changes

struct ChangesArgs : ReadArgs {
  int64_t since = 0;
};

int RunChanges(const ChangesArgs& args) {
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  auto changes = SettledChangesSince(**store, args.since);
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
                 {"bbox", {c.min_x, c.min_y, c.max_x, c.max_y}},
                 {"features", c.features}});
  }
  if (args.json) std::cout << j.dump(2) << "\n";
  return kExitOk;
}

// The options every surface query starts with.
void AddSurfaceOptions(CLI::App* cmd, SurfaceArgs& args) {
  cmd->add_option("store", args.store, "Store file")->required();
  cmd->add_option("--surface", args.surface, "Surface name")->required();
  cmd->add_flag("--json", args.json, "Print JSON");
}

void RegisterLocate(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<LocateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "locate", "The triangle holding a point and z there, or those of every point of a file");
  AddSurfaceOptions(cmd, *args);
  cmd->add_option("x", args->x, "X in the store's CRS");
  cmd->add_option("y", args->y, "Y in the store's CRS");
  cmd->add_option("--points", args->points,
                  "Locate every point of FILE (x,y lines, CSV with a header, any OGR point "
                  "layer; - for stdin); prints CSV, or JSON lines with --json");
  cmd->callback([=] { *exit_code = RunLocate(*args); });
}

void RegisterStar(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<StarArgs>();
  CLI::App* cmd =
      app.add_subcommand("star", "The triangles and vertices around a vertex, counter-clockwise");
  AddSurfaceOptions(cmd, *args);
  cmd->add_option("vertex", args->vertex, "Vertex id")->required();
  cmd->callback([=] { *exit_code = RunStar(*args); });
}

void RegisterTriangles(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<TrianglesArgs>();
  CLI::App* cmd =
      app.add_subcommand("triangles", "The triangles of a window (--bbox) or a feature");
  AddSurfaceOptions(cmd, *args);
  cmd->add_option("--bbox", args->bbox, "minx,miny,maxx,maxy: the triangles meeting the window");
  cmd->add_option("--feature", args->feature, "The triangles inside polygon feature ID");
  cmd->add_flag("--visible-only", args->visible_only, "Leave out invisible triangles");
  cmd->add_option("--tag", args->tag, "Only the triangles with this tag");
  cmd->callback([=] { *exit_code = RunTriangles(*args); });
}

void RegisterNeighbours(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<NeighboursArgs>();
  CLI::App* cmd = app.add_subcommand("neighbours", "A triangle's neighbours and shared edges");
  cmd->alias("neighbors");
  AddSurfaceOptions(cmd, *args);
  cmd->add_option("id", args->id, "Triangle id")->required();
  cmd->callback([=] { *exit_code = RunNeighbours(*args); });
}

void RegisterProfile(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<ProfileArgs>();
  CLI::App* cmd = app.add_subcommand(
      "profile", "The surface along a polyline: every edge crossing, its distance and z");
  AddSurfaceOptions(cmd, *args);
  cmd->add_option("--line", args->line, "The line's points: \"x,y x,y ...\"");
  cmd->add_option("--line-file", args->line_file,
                  "The line from FILE: x,y lines, an OGR point layer or one OGR line");
  cmd->add_option("--plot", args->plot, "Also draw the profile as a PNG image at this path");
  cmd->add_option("--width", args->width, "Plot width in pixels (default 1000)");
  cmd->add_option("--height", args->height, "Plot height in pixels (default 400)");
  cmd->callback([=] { *exit_code = RunProfile(*args); });
}

}  // namespace

void RegisterQueryCommands(CLI::App& app, int* exit_code) {
  RegisterLocate(app, exit_code);
  RegisterStar(app, exit_code);
  RegisterTriangles(app, exit_code);
  RegisterNeighbours(app, exit_code);
  RegisterProfile(app, exit_code);

  auto ch_args = std::make_shared<ChangesArgs>();
  CLI::App* ch = app.add_subcommand("changes", "Write transactions after --since, oldest first");
  ch->add_option("store", ch_args->store, "Store file")->required();
  ch->add_option("--since", ch_args->since, "Transaction number (default 0: all)");
  ch->add_flag("--json", ch_args->json, "Print JSON");
  ch->callback([=] { *exit_code = RunChanges(*ch_args); });
}

}  // namespace tinbase::cli
