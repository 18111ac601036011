// Mass points (issue 28, docs/BENCHMARKS.md "Mass points"): 10,000 survey points into the
// ~1e6-triangle store (bench/store_1e6.h), three ways, alternated in rounds so the ratios are
// taken on the same machine state:
//   - `mass`: one `points add` of all of them (db/edit/mass_points.h), one transaction;
//   - `single`: the same points as single-point `points add` transactions, the first kSingles
//     of them (10,000 would take minutes; the per-point time only grows with the features the
//     store gathers, so kSingles x the per-point time is a lower bound for 10,000);
//   - `cgal`: CGAL inserting them into the same triangulation in memory (the surface's CDT
//     rebuilt from its rows first, untimed; Cdt::InsertVertices, spatially sorted).
// Every round starts from a fresh copy of the store (untimed). The points lie on the surface
// (z interpolated in their triangle), so the tolerance refinement around them has nothing to do
// and each way does the same work: locate, insert, re-triangulate. Counters: medians of the
// rounds of mass_ms, single_ms_per_point, cgal_ms, and the two ratios the issue asks for.
#include <benchmark/benchmark.h>
#include <gdal.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "bench/store_1e6.h"
#include "core/geometry/cdt.h"
#include "db/edit/mass_points.h"
#include "db/point_locator.h"
#include "db/surface_store.h"

namespace tinbase {
namespace {

constexpr int kPoints = 10000;
constexpr int kSingles = 300;
constexpr int kRounds = 3;

std::string BenchDir() {
  const std::string d = (std::filesystem::temp_directory_path() / "tinbase_bench").string();
  std::filesystem::create_directories(d);
  return d;
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// A fresh copy of the 1e6 store (its WAL checkpointed into the file by the build).
std::string FreshCopy(const std::string& from) {
  const std::string to = BenchDir() + "/mass_points_work.tinbase";
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(to + suffix);
  std::filesystem::copy_file(from, to);
  return to;
}

// kPoints points inside the surface, away from its edge, z on the surface.
std::vector<TinVertex> SurveyPointsOn(const std::string& path) {
  auto store = Store::Open(path, Store::Access::kReadOnly);
  if (!store.ok()) std::abort();
  auto surface = SurfaceStore(**store).Find(kStore1e6Surface);
  if (!surface.ok()) std::abort();
  std::mt19937_64 rng(28);
  // Cell centres are DEM vertices: keep the points a fraction of a cell off them.
  std::uniform_real_distribution<double> cell(5, 700);
  std::uniform_real_distribution<double> frac(0.2, 0.8);
  PointLocator locator(**store, *surface);
  std::vector<TinVertex> out;
  auto dems = DemStore(**store).List();
  if (!dems.ok() || dems->empty()) std::abort();
  const GridGeometry& g = dems->front().geometry;
  while (static_cast<int>(out.size()) < kPoints) {
    const double x = g.MinX() + std::floor(cell(rng)) + frac(rng);
    const double y = g.MaxY() - std::floor(cell(rng)) - frac(rng);
    auto at = locator.Locate(x, y);
    if (!at.ok()) continue;
    out.push_back({x, y, at->z, VertexKind::kUser});
  }
  return out;
}

double MassAdd(const std::string& path, const std::vector<TinVertex>& points) {
  auto store = Store::Open(path);
  if (!store.ok()) std::abort();
  PointsAddOptions o;
  o.surface = kStore1e6Surface;
  o.points = points;
  o.labels.assign(points.size(), "point");
  const auto start = std::chrono::steady_clock::now();
  auto report = AddPoints(**store, o);
  const double s = Seconds(start);
  if (!report.ok()) {
    std::fprintf(stderr, "mass add: %s\n", report.status().message().c_str());
    std::abort();
  }
  return s;
}

double SingleAdds(const std::string& path, const std::vector<TinVertex>& points) {
  auto store = Store::Open(path);
  if (!store.ok()) std::abort();
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kSingles; ++i) {
    PointsAddOptions o;
    o.surface = kStore1e6Surface;
    o.points = std::vector<TinVertex>{points[static_cast<size_t>(i)]};
    o.labels = {"point"};
    if (!AddPoints(**store, o).ok()) std::abort();
  }
  return Seconds(start) / kSingles;
}

double CgalInsert(const LoadedSurface& loaded, const std::vector<TinVertex>& points) {
  Cdt cdt;
  const auto index = cdt.InsertVertices(loaded.tin.vertices);
  for (const auto& [a, b] : loaded.tin.constraints) cdt.InsertConstraint(index[a], index[b]);
  const auto start = std::chrono::steady_clock::now();
  cdt.InsertVertices(points);
  const double s = Seconds(start);
  benchmark::DoNotOptimize(cdt.FaceCount());
  return s;
}

void BM_MassPoints1e6(benchmark::State& state) {
  GDALAllRegister();
  const std::string original = Store1e6(BenchDir());
  const std::vector<TinVertex> points = SurveyPointsOn(original);
  LoadedSurface loaded;
  {
    auto store = Store::Open(original, Store::Access::kReadOnly);
    if (!store.ok()) std::abort();
    SurfaceStore surfaces(**store);
    auto read = surfaces.Load(*surfaces.Find(kStore1e6Surface));
    if (!read.ok()) std::abort();
    loaded = std::move(*read);
  }
  std::vector<double> mass, single, cgal, over_single, over_cgal;
  for (auto _ : state) {
    for (int round = 0; round < kRounds; ++round) {
      state.PauseTiming();
      std::string work = FreshCopy(original);
      state.ResumeTiming();
      mass.push_back(MassAdd(work, points));
      cgal.push_back(CgalInsert(loaded, points));
      state.PauseTiming();
      work = FreshCopy(original);
      state.ResumeTiming();
      single.push_back(SingleAdds(work, points));
      over_single.push_back(single.back() * kPoints / mass.back());
      over_cgal.push_back(mass.back() / cgal.back());
    }
  }
  state.counters["mass_ms"] = 1e3 * Median(mass);
  state.counters["single_ms_per_point"] = 1e3 * Median(single);
  state.counters["cgal_ms"] = 1e3 * Median(cgal);
  state.counters["speedup_over_single"] = Median(over_single);
  state.counters["speedup_over_single_min"] =
      *std::min_element(over_single.begin(), over_single.end());
  state.counters["mass_over_cgal"] = Median(over_cgal);
  state.counters["triangles"] = static_cast<double>(loaded.tin.triangles.size());
}
BENCHMARK(BM_MassPoints1e6)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace tinbase

BENCHMARK_MAIN();
