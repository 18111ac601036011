// The files a TIN benchmark shares with its peers, in one directory: terrain.f32 (the cells,
// row-major float32, for npm delatin and @mapbox/martini), terrain.json (at least its width and
// height), terrain.tif (the same cells as a GeoTIFF in UTM zone 32N, for `tinbase dem import`),
// and a peer's mesh as bench/peers/*.mjs write it. Used by tin_bench and dense_bench.
// Header-only; the terrain's geometry is the generated terrains' (bench/generated_terrain.h).
#pragma once

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cstdint>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "core/raster/gdal_raster.h"
#include "core/raster/grid.h"
#include "core/tin/tin.h"

namespace tinbase {

// Writes DIR/terrain.f32: the grid's cells as they lie in memory.
inline void WriteTerrainCells(const Grid& grid, const std::string& dir) {
  std::ofstream(dir + "/terrain.f32", std::ios::binary)
      .write(reinterpret_cast<const char*>(grid.cells.data()),
             static_cast<std::streamsize>(grid.cells.size() * sizeof(float)));
}

// The terrain of DIR (terrain.json's width and height, terrain.f32's cells) on the generated
// terrains' origin with square cells of `cell` metres.
inline Grid LoadTerrain(const std::string& dir, double cell) {
  std::ifstream meta_in(dir + "/terrain.json");
  const auto meta = nlohmann::json::parse(meta_in);
  const int64_t w = meta["width"], h = meta["height"];
  Grid grid;
  grid.geometry = GridGeometry{500000, 5200000, cell, -cell, w, h};
  grid.cells.resize(static_cast<size_t>(w * h));
  std::ifstream in(dir + "/terrain.f32", std::ios::binary);
  in.read(reinterpret_cast<char*>(grid.cells.data()),
          static_cast<std::streamsize>(grid.cells.size() * sizeof(float)));
  return grid;
}

// Writes `grid` as a GeoTIFF at `path` in EPSG:32632 (a projected CRS, so the store takes it as
// is). Errors as WriteGeoTiff.
inline Status WriteUtmGeoTiff(Grid grid, const std::string& path) {
  OGRSpatialReference srs;
  srs.importFromEPSG(32632);
  char* wkt = nullptr;
  srs.exportToWkt(&wkt);
  grid.crs_wkt = wkt;
  CPLFree(wkt);
  return WriteGeoTiff(grid, path);
}

// A peer's mesh (bench/peers/*.mjs: vertex and triangle counts, then grid columns and rows, then
// corner indices, all uint32) as a Tin on `grid`, z the cells' values.
inline Tin ReadPeerMesh(const std::string& path, const Grid& grid) {
  std::ifstream in(path, std::ios::binary);
  uint32_t counts[2] = {0, 0};
  in.read(reinterpret_cast<char*>(counts), sizeof counts);
  std::vector<uint32_t> xy(2 * counts[0]), tri(3 * counts[1]);
  in.read(reinterpret_cast<char*>(xy.data()), static_cast<std::streamsize>(xy.size() * 4));
  in.read(reinterpret_cast<char*>(tri.data()), static_cast<std::streamsize>(tri.size() * 4));
  Tin tin;
  const GridGeometry& g = grid.geometry;
  for (size_t i = 0; i < counts[0]; ++i) {
    const int64_t c = xy[2 * i], r = xy[2 * i + 1];
    tin.vertices.push_back(
        TinVertex{g.CellCenterX(c), g.CellCenterY(r), grid.At(c, r), VertexKind::kDem});
  }
  for (size_t t = 0; t < counts[1]; ++t) {
    TinTriangle triangle;
    triangle.v = {tri[3 * t], tri[3 * t + 1], tri[3 * t + 2]};
    tin.triangles.push_back(triangle);
  }
  return tin;
}

}  // namespace tinbase
