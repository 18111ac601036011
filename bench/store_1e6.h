// The ~1e6-triangle store of issue 24's benchmarks (locate_bench, export_bench): the generated
// terrain (bench/generated_terrain.h) at 1 m over 709 x 709 cells, EPSG:32632, imported as a DEM
// and built greedy at 1 mm, which keeps nearly every point (~1e6 triangles). Built once into
// DIR/locate_1e6.tinbase (under a temporary name until it is complete), then reused.
// Header-only; aborts with a message when the store cannot be built.
#pragma once

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "bench/generated_terrain.h"
#include "core/geometry/crs.h"
#include "core/raster/gdal_raster.h"
#include "db/dem_store.h"
#include "db/surface_builder.h"

namespace tinbase {

inline constexpr const char* kStore1e6Surface = "terrain";

// REQUIRES: GDALAllRegister() has run.
inline std::string Store1e6(const std::string& dir) {
  const std::string path = dir + "/locate_1e6.tinbase";
  if (std::filesystem::exists(path)) return path;
  const auto die = [&](const Status& s) {
    std::fprintf(stderr, "building %s: %s\n", path.c_str(), s.message().c_str());
    std::exit(1);
  };
  std::filesystem::create_directories(dir);
  Grid grid = GeneratedTerrain(709);
  auto crs = Crs::FromUserInput("EPSG:32632");
  if (!crs.ok()) die(crs.status());
  grid.crs_wkt = crs->Wkt();
  const std::string tif = dir + "/store_1e6_dem.tif";
  if (Status s = WriteGeoTiff(grid, tif); !s.ok()) die(s);
  const std::string building = path + ".building";
  std::filesystem::remove(building);
  {
    auto store = Store::Create(building, "");
    if (!store.ok()) die(store.status());
    DemStore dems(**store);
    if (auto imported = dems.Import({tif}, {}); !imported.ok()) die(imported.status());
    SurfaceBuildOptions o;
    o.surface = kStore1e6Surface;
    o.greedy.tolerance = 1e-3;
    auto built = BuildSurfaceFromDem(**store, o);
    if (!built.ok()) die(built.status());
    std::printf("built %s: %" PRId64 " triangles\n", path.c_str(), built->triangles);
  }
  std::filesystem::rename(building, path);
  std::filesystem::remove(tif);
  return path;
}

}  // namespace tinbase
