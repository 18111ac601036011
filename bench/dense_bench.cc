// dense_bench: issue 30's dense TINs on rough terrain. Writes the rough terrain for every tool and
// scores each tool's mesh against every cell with the same code (CompareTinToGrid), so
// `tinbase tin build`, hmm and npm delatin compare at their true max error. Timing is done by
// scripts/bench-dense.sh around whole processes; nothing here is timed.
//
//   dense_bench export --size N --out DIR
//       DIR/terrain.{f32,tif,png,json}: the f32 grid for delatin, a GeoTIFF (30 m cells, UTM)
//       for `tinbase dem import`, a 16-bit PNG for hmm, and the PNG's z scale in the JSON.
//   dense_bench score --dir DIR (--stl F | --mesh F | --store F --surface S) [--match]
//       One JSON line: triangles, vertices and the true max and RMS error of the mesh; with
//       --match, also the triangles of tinbase's greedy held to that true max error.
//   dense_bench build --dir DIR --error E [--runs N]
//       The greedy builder alone, in memory: best wall time of N runs, triangles, and a hash of
//       the TIN (vertices and triangles in order), so a change to the builder shows both its
//       speed and whether the TIN stayed the same.
#include <gdal_priv.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench/generated_terrain.h"
#include "bench/terrain_files.h"
#include "core/raster/gdal_raster.h"
#include "core/tin/greedy_builder.h"
#include "core/tin/tin_hash.h"
#include "core/tin/tin_raster.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {
namespace {

// The cell size RoughTerrain gives the terrain, in metres.
constexpr double kRoughCell = 30;

// hmm's input: a 16-bit grey PNG of the cells' levels (value / step).
bool WritePng16(const Grid& grid, double step, const std::string& path) {
  const int w = static_cast<int>(grid.geometry.width), h = static_cast<int>(grid.geometry.height);
  std::vector<uint16_t> levels(grid.cells.size());
  for (size_t i = 0; i < levels.size(); ++i)
    levels[i] = static_cast<uint16_t>(std::lround(grid.cells[i] / step));
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* png = GetGDALDriverManager()->GetDriverByName("PNG");
  if (mem == nullptr || png == nullptr) return false;
  GDALDataset* ds = mem->Create("", w, h, 1, GDT_UInt16, nullptr);
  if (ds == nullptr) return false;
  const CPLErr err = ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, w, h, levels.data(), w, h,
                                                    GDT_UInt16, 0, 0, nullptr);
  GDALDataset* out = err == CE_None
                         ? png->CreateCopy(path.c_str(), ds, FALSE, nullptr, nullptr, nullptr)
                         : nullptr;
  const bool ok = out != nullptr;
  if (out != nullptr) GDALClose(out);
  GDALClose(ds);
  return ok;
}

int Export(int64_t size, const std::string& out) {
  std::filesystem::create_directories(out);
  auto [grid, step] = RoughTerrain(size);
  WriteTerrainCells(grid, out);
  // hmm's z is level / 65535 * zscale: zscale = 65535 * step gives the cells' metres.
  std::ofstream(out + "/terrain.json") << nlohmann::json{
      {"width", size},
      {"height", size},
      {"zscale", 65535 * step},
      {"step", step},
      {"cell", 30}}.dump();
  if (!WritePng16(grid, step, out + "/terrain.png")) {
    std::cerr << "could not write " << out << "/terrain.png\n";
    return 1;
  }
  const Status s = WriteUtmGeoTiff(std::move(grid), out + "/terrain.tif");
  if (!s.ok()) std::cerr << s.ToString() << "\n";
  return s.ok() ? 0 : 1;
}

// hmm's binary STL as a Tin on `grid`: x is the column, y is (height - 1 - row), and each
// vertex's z is taken from the cell (hmm writes the same level in float).
Tin ReadStl(const std::string& path, const Grid& grid) {
  std::ifstream in(path, std::ios::binary);
  char header[84];
  in.read(header, sizeof header);
  uint32_t count = 0;
  std::memcpy(&count, header + 80, 4);
  const GridGeometry& g = grid.geometry;
  std::vector<int32_t> index(static_cast<size_t>(g.CellCount()), -1);
  Tin tin;
  tin.triangles.reserve(count);
  char record[50];
  for (uint32_t t = 0; t < count && in.read(record, sizeof record); ++t) {
    TinTriangle triangle;
    for (int k = 0; k < 3; ++k) {
      float p[3];
      std::memcpy(p, record + 12 + 12 * k, 12);
      const auto col = static_cast<int64_t>(std::lround(p[0]));
      const int64_t row = g.height - 1 - std::lround(p[1]);
      int32_t& at = index[static_cast<size_t>(row * g.width + col)];
      if (at < 0) {
        at = static_cast<int32_t>(tin.vertices.size());
        tin.vertices.push_back(
            TinVertex{g.CellCenterX(col), g.CellCenterY(row), grid.At(col, row), VertexKind::kDem});
      }
      triangle.v[k] = static_cast<uint32_t>(at);
    }
    tin.triangles.push_back(triangle);
  }
  return tin;
}

Result<Tin> ReadStoreSurface(const std::string& path, const std::string& name) {
  TB_ASSIGN_OR_RETURN(auto store, Store::Open(path));
  SurfaceStore surfaces(*store);
  TB_ASSIGN_OR_RETURN(SurfaceInfo surface, surfaces.Find(name));
  TB_ASSIGN_OR_RETURN(LoadedSurface loaded, surfaces.Load(surface));
  return std::move(loaded.tin);
}

int Score(const std::string& dir, const std::string& stl, const std::string& mesh,
          const std::string& store, const std::string& surface, bool match) {
  const Grid grid = LoadTerrain(dir, kRoughCell);
  Tin tin;
  if (!stl.empty()) {
    tin = ReadStl(stl, grid);
  } else if (!mesh.empty()) {
    tin = ReadPeerMesh(mesh, grid);  // bench/peers/run_delatin.mjs
  } else {
    auto loaded = ReadStoreSurface(store, surface);
    if (!loaded.ok()) {
      std::cerr << loaded.status().ToString() << "\n";
      return 1;
    }
    tin = std::move(loaded).value();
  }
  const TinGridError e = CompareTinToGrid(tin, grid);
  nlohmann::json line{{"triangles", tin.triangles.size()},
                      {"vertices", tin.vertices.size()},
                      {"max_error", e.max_error},
                      {"rms_error", e.rms_error},
                      {"uncovered", e.uncovered}};
  if (match) {
    // tinbase's greedy held to the error the peer really kept: triangles at equal true error.
    auto same = BuildGreedyTin(grid, {.tolerance = e.max_error});
    if (!same.ok()) {
      std::cerr << same.status().ToString() << "\n";
      return 1;
    }
    line["tinbase_at_same_error"] = same->triangles.size();
  }
  std::cout << line.dump() << "\n";
  return 0;
}

int Build(const std::string& dir, double error, int runs) {
  const Grid grid = LoadTerrain(dir, kRoughCell);
  double best = 1e300;
  Tin tin;
  GreedyReport report;
  for (int i = 0; i < runs; ++i) {
    const auto start = std::chrono::steady_clock::now();
    auto built = BuildGreedyTin(grid, {.tolerance = error}, &report);
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!built.ok()) {
      std::cerr << built.status().ToString() << "\n";
      return 1;
    }
    best = std::min(best, s);
    tin = std::move(built).value();
  }
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(TinHash(tin)));
  std::cout << nlohmann::json{{"error", error},
                              {"seconds", best},
                              {"triangles", tin.triangles.size()},
                              {"max_error", report.max_error},
                              {"rms_error", report.rms_error},
                              {"hash", hash}}
                   .dump()
            << "\n";
  return 0;
}

}  // namespace
}  // namespace tinbase

int main(int argc, char** argv) {
  GDALAllRegister();
  CLI::App app{"issue 30: dense TINs on rough terrain"};
  app.require_subcommand(1);
  int64_t size = 2049;
  std::string out, dir, stl, mesh, store, surface = "s";
  bool match = false;
  int rc = 0;
  CLI::App* exp = app.add_subcommand("export", "Write the rough terrain for every tool");
  exp->add_option("--size", size);
  exp->add_option("--out", out)->required();
  exp->callback([&] { rc = tinbase::Export(size, out); });
  CLI::App* score = app.add_subcommand("score", "True error of one tool's mesh");
  score->add_option("--dir", dir)->required();
  score->add_option("--stl", stl, "hmm's binary STL");
  score->add_option("--mesh", mesh, "a mesh of bench/peers/run_delatin.mjs");
  score->add_option("--store", store, "a store holding the surface");
  score->add_option("--surface", surface);
  score->add_flag("--match", match, "Also tinbase's triangles at the mesh's true max error");
  score->callback([&] { rc = tinbase::Score(dir, stl, mesh, store, surface, match); });
  double error = 1;
  int runs = 1;
  CLI::App* build = app.add_subcommand("build", "The greedy builder alone, timed, with a hash");
  build->add_option("--dir", dir)->required();
  build->add_option("--error", error);
  build->add_option("--runs", runs);
  build->callback([&] { rc = tinbase::Build(dir, error, runs); });
  CLI11_PARSE(app, argc, argv);
  return rc;
}
