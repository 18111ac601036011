// tin_bench: tinbase's terrain TIN builders side by side with their peers (npm delatin and
// @mapbox/martini, run by bench/peers/run_peers.mjs; CGAL's bulk Delaunay), every result's true
// error measured here with the same code (CompareTinToGrid). Driven by scripts/bench-tin.sh.
//
//   tin_bench export --size N --out DIR        generated N x N terrain -> DIR/terrain.{f32,tif}
//   tin_bench export --real FILE --size N ...  an N x N window of a real DEM instead
//   tin_bench measure --dir DIR --errors E,... tinbase's builders + the peers' meshes in DIR
//   tin_bench delaunay --points N              CGAL alone against points -> store
#include <gdal_priv.h>
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench/generated_terrain.h"
#include "bench/terrain_files.h"
#include "core/geometry/cdt.h"
#include "core/raster/gdal_raster.h"
#include "core/tin/edge_collapse.h"
#include "core/tin/greedy_builder.h"
#include "core/tin/grid_triangulation.h"
#include "core/tin/rtin_builder.h"
#include "core/tin/tin_raster.h"
#include "core/tin/vip_builder.h"
#include "db/dem_store.h"
#include "db/point_import.h"
#include "db/surface_builder.h"

namespace tinbase {
namespace {

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

template <typename Fn>
double Time(Fn&& fn) {
  const auto start = std::chrono::steady_clock::now();
  fn();
  return Seconds(start);
}

// Timed the way bench/peers/run_peers.mjs times a peer, so the two compare like for like: one
// warm-up run, then the best of 3 (1 run above 5e6 cells).
template <typename Fn>
double TimeLikePeers(const Grid& grid, Fn&& fn) {
  fn();
  const int runs = grid.geometry.CellCount() > 5'000'000 ? 1 : 3;
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < runs; ++i) best = std::min(best, Time(fn));
  return best;
}

// An N x N window of a real DEM from row 0 and column col0, geometry reset to 1-unit cells; voids
// take the value of the nearest valid cell to their left on the row (peers cannot take NaN).
Result<Grid> RealWindow(const std::string& path, int64_t size, int64_t col0) {
  TB_ASSIGN_OR_RETURN(GdalRaster raster, GdalRaster::Open(path));
  TB_ASSIGN_OR_RETURN(Grid full, raster.Read());
  col0 = std::clamp<int64_t>(col0, 0, full.geometry.width - 1);
  size = std::min({size, full.geometry.width - col0, full.geometry.height});
  Grid grid;
  grid.geometry = GridGeometry{500000, 5200000, 1, -1, size, size};
  for (int64_t r = 0; r < size; ++r) {
    float last = 0;
    for (int64_t c = 0; c < size; ++c) {
      float v = full.At(col0 + c, r);
      if (std::isnan(v)) v = last;
      grid.cells.push_back(v);
      last = v;
    }
  }
  return grid;
}

int Export(const std::string& real, int64_t size, int64_t col0, const std::string& out) {
  std::filesystem::create_directories(out);
  Grid grid;
  if (real.empty()) {
    grid = GeneratedTerrain(size);
  } else {
    auto window = RealWindow(real, size, col0);
    if (!window.ok()) {
      std::cerr << window.status().ToString() << "\n";
      return 1;
    }
    grid = std::move(window).value();
  }
  WriteTerrainCells(grid, out);
  std::ofstream(out + "/terrain.json") << nlohmann::json{
      {"width", grid.geometry.width},
      {"height", grid.geometry.height},
      {"source",
       real.empty() ? "generated" : real}}.dump();
  // The same cells as a GeoTIFF in a projected CRS, for the store path (dem import).
  const Status s = WriteUtmGeoTiff(std::move(grid), out + "/terrain.tif");
  if (!s.ok()) std::cerr << s.ToString() << "\n";
  return s.ok() ? 0 : 1;
}

struct Row {
  std::string method;
  double error = 0;  // the nominal max error (tolerance, threshold) asked for
  int64_t triangles = 0;
  double max_error = 0, rms_error = 0;  // measured here against every cell
  double seconds = 0;
};

void Print(const Row& r, std::ostream& csv) {
  std::printf("| %-14s | %5g | %9lld | %8.3f | %7.3f | %8.3f |\n", r.method.c_str(), r.error,
              static_cast<long long>(r.triangles), r.max_error, r.rms_error, r.seconds);
  csv << r.method << "," << r.error << "," << r.triangles << "," << r.max_error << ","
      << r.rms_error << "," << r.seconds << "\n";
}

Row Measured(const std::string& method, double error, const Tin& tin, const Grid& grid,
             double seconds) {
  const TinGridError e = CompareTinToGrid(tin, grid);
  return Row{method,      error,       static_cast<int64_t>(tin.triangles.size()),
             e.max_error, e.rms_error, seconds};
}

// Greedy through the store, as `tinbase tin build` runs it: build (streaming the DEM) + write.
Row GreedyWithStore(const std::string& dir, double tolerance) {
  const std::string path = dir + "/bench.tinbase";
  std::filesystem::remove(path);
  std::filesystem::remove(path + "-wal");
  auto store = Store::Create(path, "");
  Row row{"greedy+store", tolerance};
  if (!store.ok() || !DemStore(**store).Import({dir + "/terrain.tif"}, {}).ok()) return row;
  SurfaceBuildOptions options;
  options.surface = "s";
  options.greedy.tolerance = tolerance;
  auto report = BuildSurfaceFromDem(**store, options);
  if (!report.ok()) {
    std::cerr << report.status().ToString() << "\n";
    return row;
  }
  row.triangles = report->triangles;
  row.max_error = report->quality.max_error;
  row.rms_error = report->quality.rms_error;
  row.seconds = report->build_seconds + report->write_seconds;
  return row;
}

int Measure(const std::string& dir, const std::vector<double>& errors, bool all_methods,
            bool store) {
  const Grid grid = LoadTerrain(dir, 1);
  std::map<std::pair<std::string, double>, double> peer_seconds;
  std::ifstream peers(dir + "/peers.jsonl");
  for (std::string line; std::getline(peers, line);) {
    const auto j = nlohmann::json::parse(line);
    peer_seconds[{j["peer"], j["error"]}] = j["seconds"];
  }
  std::ofstream csv(dir + "/results.csv");
  csv << "method,error,triangles,max_error,rms_error,seconds\n";
  std::printf("| method         | error | triangles | true max |     RMS |  seconds |\n");
  std::printf("|---|---|---|---|---|---|\n");
  // One untimed pass of the timed builders first. The peers run in a Node process whose heap has
  // grown by the time they are timed; here the first error's runs, warm-up included, found
  // freshly mapped memory (glibc returns large blocks until its thresholds grow with them) and
  // took several times what the same builds took at the next error.
  if (!errors.empty()) {
    (void)BuildGreedyTin(grid, {.tolerance = errors.front()});
    (void)BuildRtinTin(grid, {.tolerance = errors.front()});
  }
  for (double e : errors) {
    // value() of the temporary moves the mesh out (`*` would copy it inside the timed region).
    Tin greedy;
    const double greedy_s =
        TimeLikePeers(grid, [&] { greedy = BuildGreedyTin(grid, {.tolerance = e}).value(); });
    Print(Measured("greedy", e, greedy, grid, greedy_s), csv);
    if (store) Print(GreedyWithStore(dir, e), csv);
    Tin rtin;
    const double rtin_s =
        TimeLikePeers(grid, [&] { rtin = BuildRtinTin(grid, {.tolerance = e}).value(); });
    Print(Measured("rtin", e, rtin, grid, rtin_s), csv);
    for (const std::string peer : {"delatin", "martini"}) {
      std::ostringstream name;
      name << dir << "/" << peer << "_" << e << ".mesh";
      if (!std::filesystem::exists(name.str()) || !peer_seconds.count({peer, e})) continue;
      const Row row =
          Measured(peer, e, ReadPeerMesh(name.str(), grid), grid, peer_seconds[{peer, e}]);
      Print(row, csv);
      if (std::string(peer) == "delatin") {
        // tinbase greedy held to the error delatin really kept: triangles at equal true error.
        Tin same;
        const double s =
            Time([&] { same = BuildGreedyTin(grid, {.tolerance = row.max_error}).value(); });
        Print(Measured("greedy@delatin", e, same, grid, s), csv);
      }
    }
    if (all_methods) {
      Tin vip;
      const double vip_s = Time([&] { vip = *BuildVipTin(grid, {.threshold = e}); });
      Print(Measured("vip", e, vip, grid, vip_s), csv);
      Tin collapsed;
      const double collapse_s = Time([&] {
        collapsed = *CollapseToFaceBudget(GridTriangulation(grid),
                                          {.faces = static_cast<int64_t>(greedy.triangles.size())},
                                          nullptr, &grid);
      });
      Print(Measured("collapse", e, collapsed, grid, collapse_s), csv);
    }
    std::fflush(stdout);
  }
  return 0;
}

int64_t PeakRssKib() {
  struct rusage usage {};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

// LiDAR-like points: uniform random x, y over a square at ~1 point per m^2, z a smooth terrain.
std::vector<TinVertex> LidarLikePoints(int64_t n) {
  std::mt19937_64 rng(7);
  const double side = std::sqrt(static_cast<double>(n));
  std::uniform_real_distribution<double> u(0, side);
  std::vector<TinVertex> points;
  points.reserve(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) {
    const double x = u(rng), y = u(rng);
    points.push_back(TinVertex{500000 + x, 5200000 + y,
                               300 + 40 * std::sin(x / 90) * std::cos(y / 70), VertexKind::kLidar});
  }
  return points;
}

int Delaunay(int64_t n, const std::string& dir) {
  const std::vector<TinVertex> points = LidarLikePoints(n);
  // CGAL alone: the ceiling (spatially sorted bulk insertion, tinbase's Cdt adapter adds only
  // each vertex's index).
  double cgal_s = 0;
  {
    Cdt cdt;
    cgal_s = Time([&] { cdt.InsertVertices(points); });
  }
  // tinbase: an XYZ file to a checked-in store surface, as `tinbase points import` does it.
  std::filesystem::create_directories(dir);
  const std::string xyz = dir + "/points.xyz", path = dir + "/points.tinbase";
  {
    std::ofstream out(xyz);
    out.precision(12);
    for (const TinVertex& p : points) out << p.x << " " << p.y << " " << p.z << "\n";
  }
  std::filesystem::remove(path);
  std::filesystem::remove(path + "-wal");
  auto store = Store::Create(path, "EPSG:32632");
  if (!store.ok()) return 1;
  PointImportOptions options;
  options.file = xyz;
  options.surface = "lidar";
  Result<PointImportReport> report = Status::Ok();
  const double store_s = Time([&] { report = ImportPoints(**store, options); });
  if (!report.ok()) {
    std::cerr << report.status().ToString() << "\n";
    return 1;
  }
  store->reset();
  const auto bytes =
      std::filesystem::file_size(path) +
      (std::filesystem::exists(path + "-wal") ? std::filesystem::file_size(path + "-wal") : 0);
  std::printf("| %lld | %.0f | %.0f | %.2f | %.0f | %lld |\n", static_cast<long long>(n),
              n / cgal_s, n / store_s, cgal_s / store_s, static_cast<double>(bytes) / n,
              static_cast<long long>(PeakRssKib() / 1024));
  return 0;
}

std::vector<double> ParseList(const std::string& text) {
  std::vector<double> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) out.push_back(std::stod(item));
  return out;
}

}  // namespace
}  // namespace tinbase

int main(int argc, char** argv) {
  GDALAllRegister();
  CLI::App app{"tinbase TIN builder benchmark"};
  app.require_subcommand(1);
  int64_t size = 1025, points = 1000000, col0 = 0;
  std::string out, real, dir, errors = "0.5,1,5,20";
  bool all = false, store = false;
  int rc = 0;
  CLI::App* exp = app.add_subcommand("export", "Write a terrain for the peers and tinbase");
  exp->add_option("--size", size);
  exp->add_option("--real", real, "Window of this real DEM instead of the generated terrain");
  exp->add_option("--col", col0, "First column of the real DEM's window (rows start at 0)");
  exp->add_option("--out", out)->required();
  exp->callback([&] { rc = tinbase::Export(real, size, col0, out); });
  CLI::App* measure = app.add_subcommand("measure", "tinbase's builders and the peers' meshes");
  measure->add_option("--dir", dir)->required();
  measure->add_option("--errors", errors);
  measure->add_flag("--all", all, "Also VIP (threshold = error) and collapse (greedy's faces)");
  measure->add_flag("--store", store, "Also greedy through a store: build + write");
  int threads = 0;
  measure->add_option("--threads", threads, "At most this many threads (0: one per core)");
  measure->callback([&] {
    std::optional<tbb::global_control> limit;
    if (threads > 0)
      limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
    rc = tinbase::Measure(dir, tinbase::ParseList(errors), all, store);
  });
  CLI::App* delaunay = app.add_subcommand("delaunay", "CGAL alone against points -> store");
  delaunay->add_option("--points", points);
  delaunay->add_option("--dir", dir)->required();
  delaunay->callback([&] { rc = tinbase::Delaunay(points, dir); });
  CLI11_PARSE(app, argc, argv);
  return rc;
}
