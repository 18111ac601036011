// dem_bench: the DEM store against GDAL reading the same cells from a tiled ZSTD GeoTIFF with
// predictor 3 (issue 3): random 256 x 256 window reads, stored size, warm point samples, import
// time and peak memory. One run, one process (the import runs as `tinbase dem import` in a child
// so its peak RSS is its own). Driven by scripts/bench-dem.sh.
//
//   dem_bench --size 8192 --dir DIR           the generated terrain (written once, then reused)
//   dem_bench --real FILE --dir DIR           a real DEM (imported, its level 0 written as GeoTIFF)
#include <benchmark/benchmark.h>
#include <cpl_conv.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "bench/generated_terrain.h"
#include "core/raster/gdal_raster.h"
#include "db/dem_block_cache.h"
#include "db/dem_store.h"
#include "db/sql/connection.h"

namespace tinbase {
namespace {

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Writes `grid` as a GeoTIFF with `options` (GDAL creation options), EPSG:32632 unless it has a
// CRS of its own.
bool WriteTiff(const Grid& grid, const std::string& path, const std::vector<std::string>& options) {
  std::vector<char*> argv;
  for (const std::string& o : options) argv.push_back(const_cast<char*>(o.c_str()));
  argv.push_back(nullptr);
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  const GridGeometry& g = grid.geometry;
  GDALDataset* ds = gtiff->Create(path.c_str(), static_cast<int>(g.width),
                                  static_cast<int>(g.height), 1, GDT_Float32, argv.data());
  if (ds == nullptr) return false;
  double gt[6] = {g.origin_x, g.cell_x, 0, g.origin_y, 0, g.cell_y};
  ds->SetGeoTransform(gt);
  OGRSpatialReference srs;
  if (grid.crs_wkt.empty())
    srs.importFromEPSG(32632);
  else
    srs.importFromWkt(grid.crs_wkt.c_str());
  ds->SetSpatialRef(&srs);
  ds->GetRasterBand(1)->SetNoDataValue(std::nan(""));
  const CPLErr err = ds->GetRasterBand(1)->RasterIO(
      GF_Write, 0, 0, static_cast<int>(g.width), static_cast<int>(g.height),
      const_cast<float*>(grid.cells.data()), static_cast<int>(g.width), static_cast<int>(g.height),
      GDT_Float32, 0, 0, nullptr);
  GDALClose(ds);
  return err == CE_None;
}

const std::vector<std::string> kZstdTiff = {"TILED=YES", "BLOCKXSIZE=256", "BLOCKYSIZE=256",
                                            "COMPRESS=ZSTD", "PREDICTOR=3"};

// Adds the store's overview levels 1..levels-1 (mean, like the store's) to the GeoTIFF at
// `path`, compressed as its level 0.
bool AddOverviews(const std::string& path, int levels) {
  CPLSetConfigOption("COMPRESS_OVERVIEW", "ZSTD");
  CPLSetConfigOption("PREDICTOR_OVERVIEW", "3");
  GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_UPDATE);
  if (ds == nullptr) return false;
  std::vector<int> factors;
  for (int level = 1; level < levels; ++level) factors.push_back(1 << level);
  const CPLErr err = ds->BuildOverviews("AVERAGE", static_cast<int>(factors.size()), factors.data(),
                                        0, nullptr, nullptr, nullptr, nullptr);
  GDALClose(ds);
  return err == CE_None;
}

struct ImportRun {
  double seconds = 0;
  int64_t peak_rss_kib = 0;
};

// `tinbase init` + `tinbase dem import` in a child process, timed, with its peak RSS.
ImportRun ImportInChild(const std::string& store, const std::string& source) {
  std::filesystem::remove(store);
  std::filesystem::remove(store + "-wal");
  const std::string init = std::string(TINBASE_CLI) + " init '" + store + "' >/dev/null";
  if (std::system(init.c_str()) != 0) return {};
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    execl(TINBASE_CLI, "tinbase", "dem", "import", store.c_str(), source.c_str(), "--name", "dem",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  struct rusage usage {};
  wait4(pid, &status, 0, &usage);
  return ImportRun{Seconds(start), usage.ru_maxrss};
}

struct Window {
  int64_t col, row;
};

std::vector<Window> RandomWindows(const GridGeometry& g, int count) {
  std::mt19937 rng(42);
  std::uniform_int_distribution<int64_t> col(0, g.width - 256), row(0, g.height - 256);
  std::vector<Window> out;
  for (int i = 0; i < count; ++i) out.push_back({col(rng), row(rng)});
  return out;
}

DemBox BoxOf(const GridGeometry& g, const Window& w) {
  // Cell centres of the 256 x 256 cells, shrunk a little so no neighbour cell is touched.
  const double x0 = g.origin_x + (w.col + 0.25) * g.cell_x;
  const double x1 = g.origin_x + (w.col + 255.75) * g.cell_x;
  const double y0 = g.origin_y + (w.row + 0.25) * g.cell_y;
  const double y1 = g.origin_y + (w.row + 255.75) * g.cell_y;
  return DemBox{std::min(x0, x1), std::min(y0, y1), std::max(x0, x1), std::max(y0, y1)};
}

// Every rate is the best of this many timed passes: on this (virtual) machine a pass right after
// another reader freed its memory sometimes runs several times slower, for tinbase and GDAL alike.
constexpr int kPasses = 3;

// Windows per second reading `windows` through tinbase; `cold` empties the block cache first.
double TinbaseWindows(DemStore& dems, const DemInfo& dem, const std::vector<Window>& windows,
                      bool cold) {
  Grid grid;  // reused, as GDAL's caller reuses its buffer
  double best = 0;
  for (int pass = 0; pass < kPasses; ++pass) {
    const auto start = std::chrono::steady_clock::now();
    for (const Window& w : windows) {
      if (cold) DemBlockCache::Instance().Clear();
      const Status read = dems.ReadWindow(dem, BoxOf(dem.geometry, w), 0, &grid);
      if (!read.ok() || grid.cells.size() != 256 * 256) {
        std::fprintf(stderr, "window read failed: %s\n", read.ToString().c_str());
        return 0;
      }
      benchmark::DoNotOptimize(grid.cells.data());
    }
    best = std::max(best, static_cast<double>(windows.size()) / Seconds(start));
  }
  return best;
}

// The same through GDAL; `cold` drops the dataset's cached blocks before every window. `threads`
// is GDAL_NUM_THREADS (GDAL >= 3.6 decodes the tiles of one RasterIO call in parallel).
double GdalWindows(const std::string& tif, const std::vector<Window>& windows, bool cold,
                   const char* threads = "1") {
  CPLSetConfigOption("GDAL_NUM_THREADS", threads);
  std::vector<float> buffer(256 * 256);
  GDALDataset* ds = GDALDataset::Open(tif.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  // Warm: one untimed pass over the same windows first, in the same dataset (its block cache
  // lives as long as the dataset).
  for (const Window& w : windows) {
    if (cold) break;
    if (ds->GetRasterBand(1)->RasterIO(GF_Read, static_cast<int>(w.col), static_cast<int>(w.row),
                                       256, 256, buffer.data(), 256, 256, GDT_Float32, 0, 0,
                                       nullptr) != CE_None)
      return 0;
  }
  double best = 0;
  for (int pass = 0; pass < kPasses; ++pass) {
    const auto start = std::chrono::steady_clock::now();
    for (const Window& w : windows) {
      if (cold) ds->FlushCache(false);
      if (ds->GetRasterBand(1)->RasterIO(GF_Read, static_cast<int>(w.col), static_cast<int>(w.row),
                                         256, 256, buffer.data(), 256, 256, GDT_Float32, 0, 0,
                                         nullptr) != CE_None)
        return 0;
    }
    best = std::max(best, static_cast<double>(windows.size()) / Seconds(start));
  }
  GDALClose(ds);
  return best;
}

// The floor of any reader that copies a warm window out: 256 row copies from the whole level 0
// held as one flat array, no lookup of any kind.
double CopyFloorWindows(const Grid& level0, const std::vector<Window>& windows) {
  std::vector<float> buffer(256 * 256);
  const int64_t width = level0.geometry.width;
  for (int pass = 0; pass < 2; ++pass) {  // the first pass warms, like the others'
    const auto start = std::chrono::steady_clock::now();
    for (const Window& w : windows) {
      for (int64_t r = 0; r < 256; ++r)
        std::memcpy(buffer.data() + r * 256, level0.cells.data() + (w.row + r) * width + w.col,
                    256 * sizeof(float));
      benchmark::DoNotOptimize(buffer.data());
    }
    if (pass == 1) return static_cast<double>(windows.size()) / Seconds(start);
  }
  return 0;
}

void Report(const char* measure, double tinbase, double gdal, const char* goal) {
  std::printf("| %s | %.4g | %.4g | %.2f | %s |\n", measure, tinbase, gdal,
              gdal > 0 ? tinbase / gdal : 0.0, goal);
}

int Run(const std::string& real, int64_t size, const std::string& dir) {
  std::filesystem::create_directories(dir);
  const std::string store_path = dir + "/dem.tinbase", tif = dir + "/zstd.tif";
  Grid grid;
  std::string source;
  if (real.empty()) {
    source = dir + "/source.tif";
    if (!std::filesystem::exists(source)) {
      grid = GeneratedTerrain(size);
      WriteTiff(grid, source, {"TILED=YES"});
    }
  } else {
    source = real;
  }
  // TINBASE_BENCH_REUSE=1 keeps a store from an earlier run (for profiling the reads alone).
  const bool reuse =
      std::getenv("TINBASE_BENCH_REUSE") != nullptr && std::filesystem::exists(store_path);
  const ImportRun import = reuse ? ImportRun{} : ImportInChild(store_path, source);
  auto store = Store::Open(store_path);
  if (!store.ok()) return 1;
  DemStore dems(**store);
  auto dem = dems.Find("dem");
  if (!dem.ok()) return 1;
  // GDAL gets exactly the cells the store holds (for a real DEM: warped onto the store's CRS).
  auto level0 = dems.ReadGrid(*dem);
  if (!level0.ok()) return 1;
  level0->crs_wkt = dem->crs_wkt;
  WriteTiff(*level0, tif, kZstdTiff);
  const double cells = static_cast<double>(dem->geometry.CellCount());

  DemBlockCache::Instance().SetCapacity(size_t{2} << 30);
  GDALSetCacheMax64(int64_t{2} << 30);
  const std::vector<Window> windows = RandomWindows(dem->geometry, 300);
  TinbaseWindows(dems, *dem, windows, false);  // warm tinbase's cache (GDAL warms its own)
  std::printf(
      "%s: %lld x %lld cells\n\n| measure | tinbase | GDAL (ZSTD GeoTIFF) | ratio | goal |\n",
      real.empty() ? "generated" : real.c_str(), static_cast<long long>(dem->geometry.width),
      static_cast<long long>(dem->geometry.height));
  std::printf("|---|---|---|---|---|\n");
  const double gdal_warm = GdalWindows(tif, windows, false);
  Report("256x256 windows/s, warm", TinbaseWindows(dems, *dem, windows, false), gdal_warm,
         ">= 1.5x");
  Report("256x256 windows/s, copy floor (rows memcpy'd from one flat array)",
         CopyFloorWindows(*level0, windows), gdal_warm, "");
  const double cold = TinbaseWindows(dems, *dem, windows, true);
  Report("256x256 windows/s, cold cache", cold, GdalWindows(tif, windows, true), ">= 1.5x");
  Report("256x256 windows/s, cold cache, GDAL_NUM_THREADS=2", cold,
         GdalWindows(tif, windows, true, "2"), "");
  const double store_mib = static_cast<double>(std::filesystem::file_size(store_path)) / 1048576;
  const double tif_mib = static_cast<double>(std::filesystem::file_size(tif)) / 1048576;
  const std::string tif_ovr = dir + "/zstd-overviews.tif";
  std::filesystem::copy_file(tif, tif_ovr, std::filesystem::copy_options::overwrite_existing);
  Report("file MiB, both with overviews", store_mib,
         AddOverviews(tif_ovr, dem->levels)
             ? static_cast<double>(std::filesystem::file_size(tif_ovr)) / 1048576
             : 0,
         "<= 1x");
  auto level0_bytes = (*store)->db().QueryInt(
      "SELECT sum(length(data)) FROM dem_blocks WHERE level = 0 AND dem = " +
      std::to_string(dem->id));
  Report("level-0 block MiB (no overviews)",
         level0_bytes.ok() ? static_cast<double>(*level0_bytes) / 1048576 : 0, tif_mib, "<= 1x");

  // Warm point samples: the blocks of a 2048 x 2048 area (the cache holds them), random points.
  std::mt19937 rng(7);
  const GridGeometry& g = dem->geometry;
  const double span = std::min<double>(2048, static_cast<double>(std::min(g.width, g.height)) - 2);
  std::uniform_real_distribution<double> u(1, span);
  const int n = 4000000;
  std::vector<double> xs(n), ys(n), zs(n);
  for (int i = 0; i < n; ++i) {
    xs[i] = g.origin_x + u(rng) * g.cell_x;
    ys[i] = g.origin_y + u(rng) * g.cell_y;
  }
  (void)dems.SampleMany(*dem, xs, ys, zs);  // warm
  auto start = std::chrono::steady_clock::now();
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    auto z = dems.Sample(*dem, xs[i], ys[i]);
    if (z.ok()) sum += *z;
    benchmark::DoNotOptimize(sum);
  }
  const double sample_rate = n / Seconds(start);
  start = std::chrono::steady_clock::now();
  (void)dems.SampleMany(*dem, xs, ys, zs);
  const double many_rate = n / Seconds(start);
  std::printf("| bilinear samples/s, warm, 1 thread (Sample) | %.4g | | | >= 1e7 |\n", sample_rate);
  std::printf("| bilinear samples/s, warm, 1 thread (SampleMany) | %.4g | | | >= 1e7 |\n",
              many_rate);
  std::printf("| import s per Mcell | %.3g | | | |\n", import.seconds / (cells / 1e6));
  std::printf("| import peak RSS MiB | %.0f | | | < 1024 |\n\n",
              static_cast<double>(import.peak_rss_kib) / 1024);
  return 0;
}

}  // namespace
}  // namespace tinbase

int main(int argc, char** argv) {
  GDALAllRegister();
  CLI::App app{"tinbase DEM store benchmark against GDAL"};
  int64_t size = 8192;
  std::string real, dir;
  app.add_option("--size", size, "Side of the generated terrain");
  app.add_option("--real", real, "A real DEM instead of the generated terrain");
  app.add_option("--dir", dir, "Working directory")->required();
  CLI11_PARSE(app, argc, argv);
  return tinbase::Run(real, size, dir);
}
