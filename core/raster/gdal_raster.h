// GdalRaster: one elevation raster opened through GDAL, checked for what tinbase needs.
//
// Open() accepts anything GDAL reads as a raster (GeoTIFF, SRTM .hgt, ASCII grid, /vsizip/...) and
// refuses, with a message naming the file, what tinbase cannot place in the world: a missing or
// unreadable file, a file that is not a raster, no CRS, no geotransform, a rotated or south-up
// geotransform. Band 1 is the elevation; its nodata becomes NaN when read. WarpTo() reprojects
// with GDAL (bilinear, exact transformer, float32, nodata NaN) into a virtual raster that reads
// lazily from this one. A GdalRaster owns its dataset (and keeps the source of a warped one alive);
// copies share it. Thread-safety: GDAL datasets are not thread-safe; use one from one thread.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/raster/grid.h"
#include "core/raster/grid_geometry.h"

class GDALDataset;

namespace tinbase {

// Registers GDAL's drivers once per process; every entry point here calls it.
void EnsureGdalRegistered();

// Writes `grid` as a float32 GeoTIFF (DEFLATE) at `path` with its CRS and geotransform; NaN cells
// are written as grid.source_nodata when it has one, which then becomes the band's nodata (else
// NaN is). IOError naming `path` when GDAL cannot write it.
Status WriteGeoTiff(const Grid& grid, const std::string& path);

class GdalRaster {
 public:
  // NotFound when nothing exists at `path`; InvalidArgument naming `path` when GDAL cannot read it
  // as a raster or it has no band, no CRS, no geotransform, or a rotated/south-up geotransform.
  static Result<GdalRaster> Open(const std::string& path);

  // A virtual raster of band 1 reprojected onto `target` with bilinear resampling, float32 cells
  // and NaN nodata. Without `align` GDAL picks the extent and a square cell size; with it the
  // output uses `align`'s cell size and its origin lies on `align`'s grid lines (so a sheet
  // warped for an existing DEM lines up with it). InvalidArgument naming the file when GDAL
  // cannot transform it.
  Result<GdalRaster> WarpTo(const Crs& target, const GridGeometry* align = nullptr) const;

  // Band 1 as float32 cells, nodata as NaN. IOError naming the file when GDAL fails to read.
  Result<Grid> Read() const;
  // The window of `width` x `height` cells from (col, row), NaN outside the raster.
  // REQUIRES: width, height > 0.
  Result<std::vector<float>> ReadWindow(int64_t col, int64_t row, int64_t width,
                                        int64_t height) const;

  const std::string& path() const { return path_; }
  const GridGeometry& geometry() const { return geometry_; }
  const Crs& crs() const { return *crs_; }
  std::optional<double> nodata() const { return nodata_; }
  bool warped() const { return source_ != nullptr; }
  GDALDataset* dataset() const { return dataset_.get(); }

 private:
  GdalRaster() = default;
  static Result<GdalRaster> FromDataset(std::shared_ptr<GDALDataset> dataset,
                                        const std::string& path);

  std::string path_;
  std::shared_ptr<GDALDataset> source_;   // for a warped raster: the dataset it reads from
  std::shared_ptr<GDALDataset> dataset_;  // declared after source_, so closed before it
  GridGeometry geometry_;
  std::optional<Crs> crs_;
  std::optional<double> nodata_;
};

}  // namespace tinbase
