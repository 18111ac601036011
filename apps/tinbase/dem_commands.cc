// Kernels: `dem import` (rasters into the blocked DEM store) and `dem sample` (bilinear or
// nearest z at one point or at many).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "apps/tinbase/progress.h"
#include "core/base/number_text.h"
#include "core/base/output_file.h"
#include "core/export/export_format.h"
#include "core/export/tin_export.h"
#include "core/geometry/point_list.h"
#include "core/tin/edge_collapse.h"
#include "core/tin/grid_triangulation.h"
#include "db/dem_store.h"
#include "db/edit/resurvey.h"
#include "db/surface_builder.h"

namespace tinbase::cli {

namespace {

struct ImportArgs {
  std::string store;
  std::vector<std::string> files;
  std::string name;
  int block_size = 256;
  bool keep_first = false;
  bool force = false;
  bool update_surfaces = false;
};

// One line per surface brought up to date by `dem import --update-surfaces`.
void PrintResurveys(const std::vector<SurfaceResurvey>& surfaces) {
  for (const SurfaceResurvey& s : surfaces)
    std::cout << "surface '" << s.surface << "': " << s.cells_missed
              << " new cell(s) off by more than its tolerance; " << s.removed
              << " triangles replaced by " << s.added << " (" << s.refinement_points
              << " refinement points" << (s.whole_surface ? ", the whole surface" : "")
              << "); transaction " << s.tx << "\n";
}

int RunImport(const ImportArgs& args) {
  auto store = Store::Open(args.store);
  if (!store.ok()) return ReportError(store.status());
  DemStore dems(**store);
  DemImportOptions options;
  options.name = args.name;
  options.block_size = args.block_size;
  options.keep_first = args.keep_first;
  if (args.force) options.max_cells = 0;
  Stopwatch watch;
  std::vector<SurfaceResurvey> resurveyed;
  auto report = WithProgress("dem import", [&](std::function<void(double)> progress) {
    options.progress = std::move(progress);
    if (!args.update_surfaces) return dems.Import(args.files, options);
    auto updated = ImportUnderSurfaces(**store, args.files, options);
    if (!updated.ok()) return Result<DemImportReport>(updated.status());
    resurveyed = std::move(updated->surfaces);
    return Result<DemImportReport>(std::move(updated->import));
  });
  if (!report.ok()) return ReportError(report.status());
  const DemInfo& d = report->dem;
  std::cout << "imported " << args.files.size() << " file(s) into DEM '" << d.name
            << "': " << d.geometry.width << " x " << d.geometry.height << " cells, "
            << report->blocks_written << " blocks, " << Num(report->bytes_stored / 1048576.0, 3)
            << " MiB stored" << (report->warped ? ", warped onto the store's CRS" : "") << " in "
            << Num(watch.Seconds(), 3) << " s\n";
  if (report->infinite_cells > 0)
    std::cout << report->infinite_cells << " cell(s) of +/-Inf in the sources stored as nodata\n";
  PrintResurveys(resurveyed);
  return kExitOk;
}

struct SampleArgs : ReadArgs {
  std::vector<double> xy;   // one point on the command line
  std::string points_file;  // or many, one per line ("-": standard input)
  std::string dem;
  bool nearest = false;
};

// The points of --points (core/geometry/point_list.h).
Result<std::vector<Point2>> ReadPoints(const std::string& path) {
  if (path == "-") return ReadPointList(std::cin, "<stdin>");
  std::ifstream in(path);
  if (!in) return Status::NotFound("cannot open the points file '" + path + "'");
  return ReadPointList(in, path);
}

// Many points in one SampleMany call: "x y z" lines, z "nodata" where the DEM has none.
int SampleMany(DemStore& dems, const DemInfo& dem, const SampleArgs& args) {
  auto points = ReadPoints(args.points_file);
  if (!points.ok()) return ReportError(points.status());
  std::vector<double> xs, ys, zs(points->size());
  for (const Point2& p : *points) {
    xs.push_back(p.x);
    ys.push_back(p.y);
  }
  const Status s = dems.SampleMany(dem, xs, ys, zs,
                                   args.nearest ? DemSampling::kNearest : DemSampling::kBilinear);
  if (!s.ok()) return ReportError(s);
  if (args.json) {
    nlohmann::json out = nlohmann::json::array();
    for (size_t i = 0; i < zs.size(); ++i)
      out.push_back({{"x", xs[i]},
                     {"y", ys[i]},
                     {"z", std::isnan(zs[i]) ? nlohmann::json(nullptr) : nlohmann::json(zs[i])}});
    std::cout << nlohmann::json{{"dem", dem.name}, {"points", out}}.dump() << "\n";
    return kExitOk;
  }
  for (size_t i = 0; i < zs.size(); ++i)
    std::cout << Num(xs[i], 12) << " " << Num(ys[i], 12) << " "
              << (std::isnan(zs[i]) ? std::string("nodata") : Num(zs[i], 12)) << "\n";
  return kExitOk;
}

int RunSample(const SampleArgs& args) {
  if (args.points_file.empty() == args.xy.empty()) {
    return ReportError(
        Status::InvalidArgument("dem sample: give either a point (X Y) or --points FILE, not " +
                                std::string(args.xy.empty() ? "neither" : "both")));
  }
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  DemStore dems(**store);
  auto dem = ResolveDem(dems, args.dem);
  if (!dem.ok()) return ReportError(dem.status());
  if (!args.points_file.empty()) return SampleMany(dems, *dem, args);
  const double x = args.xy[0], y = args.xy[1];
  auto z = dems.Sample(*dem, x, y, args.nearest ? DemSampling::kNearest : DemSampling::kBilinear);
  if (!z.ok()) return ReportError(z.status());
  if (args.json) {
    std::cout << nlohmann::json{{"dem", dem->name}, {"x", x}, {"y", y}, {"z", *z}}.dump() << "\n";
  } else {
    std::cout << Num(*z, 12) << "\n";
  }
  return kExitOk;
}

Result<nlohmann::json> DescribeDem(DemStore& dems, const DemInfo& dem) {
  TB_ASSIGN_OR_RETURN(auto stats, dems.LevelStats(dem));
  nlohmann::json levels = nlohmann::json::array();
  int64_t bytes = 0;
  for (int level = 0; level < dem.levels; ++level) {
    const DemLevel l = LevelOf(dem, level);
    const DemLevelStats& st = stats[static_cast<size_t>(level)];
    bytes += st.bytes;
    levels.push_back({{"level", level},
                      {"width", l.geometry.width},
                      {"height", l.geometry.height},
                      {"cell_size", l.geometry.cell_x},
                      {"blocks", st.blocks},
                      {"bytes", st.bytes}});
  }
  // Raw size: the stored level-0 blocks as plain float32, what the codec saves against.
  const double raw = static_cast<double>(stats[0].blocks) * dem.block_size * dem.block_size * 4;
  const GridGeometry& g = dem.geometry;
  return nlohmann::json{{"name", dem.name},
                        {"width", g.width},
                        {"height", g.height},
                        {"cell_size", {g.cell_x, -g.cell_y}},
                        {"bbox", {g.MinX(), g.MinY(), g.MaxX(), g.MaxY()}},
                        {"block_size", dem.block_size},
                        {"levels", levels},
                        {"bytes_stored", bytes},
                        {"compression_ratio", stats[0].bytes > 0 ? raw / stats[0].bytes : 0.0}};
}

struct InfoArgs : ReadArgs {
  std::string dem;
};

int RunInfo(const InfoArgs& args) {
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  DemStore dems(**store);
  auto dem = ResolveDem(dems, args.dem);
  if (!dem.ok()) return ReportError(dem.status());
  auto j = DescribeDem(dems, *dem);
  if (!j.ok()) return ReportError(j.status());
  if (args.json) {
    std::cout << j->dump(2) << "\n";
    return kExitOk;
  }
  std::cout << "DEM '" << dem->name << "': " << dem->geometry.width << " x " << dem->geometry.height
            << " cells of " << Num(dem->geometry.cell_x) << ", blocks of " << dem->block_size
            << ", " << Num((*j)["bytes_stored"].get<double>() / 1048576.0, 4)
            << " MiB stored, level 0 compressed " << Num((*j)["compression_ratio"].get<double>(), 3)
            << "x against raw float32\n";
  for (const auto& l : (*j)["levels"])
    std::cout << "  level " << l["level"] << ": " << l["width"] << " x " << l["height"]
              << " cells of " << Num(l["cell_size"].get<double>()) << ", " << l["blocks"]
              << " blocks, " << l["bytes"] << " bytes\n";
  return kExitOk;
}

struct ClipArgs {
  std::string store;
  std::string dem;
  std::string bbox;
  int64_t max_cells = 4096 * 4096;
  std::string output;
  std::string format;  // "tif" or a mesh format; empty: from the output's extension, else tif
  int64_t faces = 0;   // mesh formats: the face budget of the edge collapse (0: none)
  std::string strategy = "quadric";
  bool json = false;
};

// "minx,miny,maxx,maxy" -> a box; InvalidArgument naming the text otherwise.
Result<DemBox> ParseBbox(const std::string& text) {
  std::vector<double> v;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = std::min(text.find(',', start), text.size());
    const std::string part = text.substr(start, comma - start);
    char* end = nullptr;
    const double d = std::strtod(part.c_str(), &end);
    if (part.empty() || end != part.c_str() + part.size() || CheckNumber(d))
      return Status::InvalidArgument("--bbox '" + text + "': '" + part + "' is not a number");
    v.push_back(d);
    start = comma + 1;
  }
  if (v.size() != 4)
    return Status::InvalidArgument("--bbox '" + text + "' needs 4 numbers: MINX,MINY,MAXX,MAXY");
  if (v[0] >= v[2] || v[1] >= v[3])
    return Status::InvalidArgument("--bbox '" + text + "': min must be below max");
  return DemBox{v[0], v[1], v[2], v[3]};
}

// What `dem clip` writes: the window as a GeoTIFF, or (paper 002) as a mesh.
struct ClipTarget {
  bool raster = true;
  ExportFormat mesh = ExportFormat::kGlb;
};

Result<ClipTarget> ResolveClipTarget(const ClipArgs& args) {
  std::string name = args.format;
  if (name.empty()) {
    const std::optional<ExportFormat> from_path = ExportFormatFromPath(args.output);
    name = from_path ? ExportFormatName(*from_path) : "tif";
  }
  if (name == "tif") {
    if (args.faces != 0)
      return Status::InvalidArgument("--faces applies to mesh formats (--format " +
                                     ExportFormatList() + "), not to a GeoTIFF");
    return ClipTarget{};
  }
  auto mesh = ParseExportFormat(name);
  if (!mesh.ok())
    return Status::InvalidArgument("unknown clip format '" + name + "' (expected one of: tif, " +
                                   ExportFormatList() + ")");
  if (args.faces != 0 && args.faces < 2)
    return Status::InvalidArgument("--faces must be at least 2, got " + std::to_string(args.faces));
  return ClipTarget{false, *mesh};
}

int RunClipRaster(const ClipArgs& args, DemStore& dems, const DemInfo& dem, const DemBox& box) {
  Stopwatch watch;
  auto out = OutputFile::Create(args.output);
  if (!out.ok()) return ReportError(out.status());
  auto clip = dems.Clip(dem, box, args.max_cells, out->temp_path());
  if (!clip.ok()) return ReportError(clip.status());
  if (Status s = out->Commit(); !s.ok()) return ReportError(s);
  if (args.json) {
    std::cout << nlohmann::json{{"output", args.output},
                                {"format", "tif"},
                                {"level", clip->level},
                                {"width", clip->geometry.width},
                                {"height", clip->geometry.height},
                                {"cell_size", clip->geometry.cell_x},
                                {"seconds", watch.Seconds()}}
                     .dump(2)
              << "\n";
    return kExitOk;
  }
  std::cout << "wrote " << args.output << ": " << clip->geometry.width << " x "
            << clip->geometry.height << " cells of " << Num(clip->geometry.cell_x) << " from level "
            << clip->level << " in " << Num(watch.Seconds(), 3) << " s\n";
  return kExitOk;
}

// Paper 002 in one command: the window at the sampling step --max-cells allows, its full grid
// triangulation, edge collapse to --faces (core/tin/edge_collapse.h), then the mesh writer.
int RunClipMesh(const ClipArgs& args, const ClipTarget& target, Store& store, DemStore& dems,
                const DemInfo& dem, const DemBox& box) {
  CollapseStrategy strategy{};
  if (!ParseCollapseStrategy(args.strategy, &strategy))
    return ReportError(Status::InvalidArgument("unknown --strategy '" + args.strategy +
                                               "' (expected quadric or paper)"));
  if (auto out = OutputFile::Create(args.output); !out.ok()) return ReportError(out.status());
  auto crs = store.GetCrs();
  if (!crs.ok()) return ReportError(crs.status());
  Stopwatch watch;
  auto level = dems.ClipLevel(dem, box, args.max_cells);
  if (!level.ok()) return ReportError(level.status());
  auto grid = dems.ReadWindow(dem, box, *level);
  if (!grid.ok()) return ReportError(grid.status());
  Tin tin = GridTriangulation(*grid);
  if (tin.triangles.empty())
    return ReportError(Status::NotFound("the window " + args.bbox + " of DEM '" + dem.name +
                                        "' holds no complete square of valid cells: nothing "
                                        "to write"));
  CollapseReport collapse;
  collapse.faces_in = collapse.faces_out = static_cast<int64_t>(tin.triangles.size());
  if (args.faces != 0) {
    CollapseOptions options;
    options.faces = args.faces;
    options.strategy = strategy;
    auto reduced = CollapseToFaceBudget(tin, options, &collapse, &*grid);
    if (!reduced.ok()) return ReportError(reduced.status());
    tin = std::move(*reduced);
  }
  ExportOptions options;
  options.format = target.mesh;
  auto report = ExportTin(tin, crs->has_value() ? &**crs : nullptr, args.output, options);
  if (!report.ok()) return ReportError(report.status());
  if (args.json) {
    std::cout << nlohmann::json{{"output", args.output},
                                {"format", ExportFormatName(target.mesh)},
                                {"level", *level},
                                {"width", grid->geometry.width},
                                {"height", grid->geometry.height},
                                {"cell_size", grid->geometry.cell_x},
                                {"faces_in", collapse.faces_in},
                                {"faces", report->triangles},
                                {"vertices", report->vertices},
                                {"budget_met", args.faces == 0 || collapse.budget_met},
                                {"max_error", collapse.max_error},
                                {"rms_error", collapse.rms_error},
                                {"bytes", report->bytes},
                                {"seconds", watch.Seconds()}}
                     .dump(2)
              << "\n";
    return kExitOk;
  }
  std::cout << "wrote " << args.output << " (" << ExportFormatName(target.mesh)
            << "): " << grid->geometry.width << " x " << grid->geometry.height << " cells of "
            << Num(grid->geometry.cell_x) << " from level " << *level << ", " << collapse.faces_in
            << " -> " << report->triangles << " faces";
  if (args.faces != 0)
    std::cout << ", max error " << Num(collapse.max_error, 4) << ", rms "
              << Num(collapse.rms_error, 4);
  std::cout << " in " << Num(watch.Seconds(), 3) << " s\n";
  return kExitOk;
}

int RunClip(const ClipArgs& args) {
  auto box = ParseBbox(args.bbox);
  if (!box.ok()) return ReportError(box.status());
  if (args.max_cells < 1) return ReportError(Status::InvalidArgument("--max-cells must be >= 1"));
  auto target = ResolveClipTarget(args);
  if (!target.ok()) return ReportError(target.status());
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  DemStore dems(**store);
  auto dem = ResolveDem(dems, args.dem);
  if (!dem.ok()) return ReportError(dem.status());
  if (target->raster) return RunClipRaster(args, dems, *dem, *box);
  return RunClipMesh(args, *target, **store, dems, *dem, *box);
}

}  // namespace

void RegisterDemCommands(CLI::App& app, int* exit_code) {
  CLI::App* dem = app.add_subcommand("dem", "The blocked DEM database");
  dem->require_subcommand(1);

  auto import_args = std::make_shared<ImportArgs>();
  CLI::App* import =
      dem->add_subcommand("import", "Import GDAL rasters (GeoTIFF, .hgt, ...) as a DEM");
  import->add_option("store", import_args->store, "Store file")->required();
  import->add_option("files", import_args->files, "Raster files")->required();
  import->add_option("--name", import_args->name, "DEM name (default: the first file's stem)");
  import->add_option("--block-size", import_args->block_size,
                     "Block edge in cells, a power of two (default 256)");
  import->add_flag("--keep-first", import_args->keep_first,
                   "Where sheets overlap, keep the earlier sheet's cells");
  import->add_flag("--force", import_args->force,
                   "Import even more than 2^34 cells (the limit that stops a raster whose header "
                   "claims an absurd size)");
  import->add_flag("--update-surfaces", import_args->update_surfaces,
                   "Into a DEM that surfaces are built on: re-triangulate each of them locally "
                   "where the new cells differ by more than its tolerance (one transaction)");
  import->callback([=] { *exit_code = RunImport(*import_args);
});

auto info_args = std::make_shared<InfoArgs>();
CLI::App* info = dem->add_subcommand("info", "Grid, levels, blocks and compression of a DEM");
info->add_option("store", info_args->store, "Store file")->required();
info->add_option("--name", info_args->dem, "DEM name (default: the only DEM)");
info->add_flag("--json", info_args->json, "Print JSON");
info->callback([=] { *exit_code = RunInfo(*info_args); });

auto clip_args = std::make_shared<ClipArgs>();
CLI::App* clip = dem->add_subcommand(
    "clip", "Write a window of a DEM as a GeoTIFF, or as a mesh reduced to --faces (paper 002)");
clip->add_option("store", clip_args->store, "Store file")->required();
clip->add_option("--name", clip_args->dem, "DEM name (default: the only DEM)");
clip->add_option("--bbox", clip_args->bbox, "MINX,MINY,MAXX,MAXY in the store's CRS")->required();
clip->add_option("--max-cells", clip_args->max_cells,
                 "Read the finest overview whose window has at most this many cells");
clip->add_option("--format", clip_args->format,
                 "tif or a mesh format: " + ExportFormatList() +
                     " (default: from the output's extension, else tif)");
clip->add_option("--faces", clip_args->faces,
                 "Mesh formats: reduce the window's grid triangulation by edge collapse to at "
                 "most this many faces");
clip->add_option("--strategy", clip_args->strategy,
                 "Edge-collapse costs: quadric (default) or paper");
clip->add_option("-o,--output", clip_args->output, "File to write")->required();
clip->add_flag("--json", clip_args->json, "Print what was written as JSON");
clip->callback([=] { *exit_code = RunClip(*clip_args); });

auto sample_args = std::make_shared<SampleArgs>();
CLI::App* sample =
    dem->add_subcommand("sample", "Bilinear elevation at a point or at many points (store CRS)");
sample->add_option("store", sample_args->store, "Store file")->required();
sample->add_option("xy", sample_args->xy, "X Y of one point in the store's CRS")->expected(2);
sample->add_option("--points", sample_args->points_file,
                   "File of points, one 'x y' or 'x,y' per line ('-': standard input); prints "
                   "'x y z' per point, z 'nodata' where there is none");
sample->add_option("--dem", sample_args->dem, "DEM name (default: the only DEM)");
sample->add_flag("--json", sample_args->json, "Print JSON");
sample->add_flag("--nearest", sample_args->nearest, "The cell's value instead of bilinear");
sample->callback([=] { *exit_code = RunSample(*sample_args); });
}  // namespace tinbase::cli

}  // namespace tinbase::cli
