// DemStore: the blocked DEM database. Elevation grids cut into fixed-size float32 blocks,
// compressed, nodata kept as NaN, one row per block in `dem_blocks` (docs/format.md).
//
// Import reads any GDAL raster; rasters in another CRS than the store's are warped onto it with
// GDAL (bilinear). A store without a CRS adopts the first DEM's: a projected CRS as is, a
// geographic one replaced by the UTM zone of the raster's centre (GeographicLib). Sampling reads
// only the blocks it needs. Thread-safety: one DemStore per Store, one thread at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/raster/grid.h"
#include "core/raster/grid_geometry.h"
#include "db/store.h"

namespace tinbase {

struct DemInfo {
  int64_t id = 0;
  std::string name;
  std::string crs_wkt;
  GridGeometry geometry;  // level 0
  int block_size = 256;
  std::optional<double> nodata;  // the first source's declared nodata, for writing rasters out
  int levels = 1;
};

struct DemImportOptions {
  std::string name;      // DEM to create or extend; empty: the first file's stem
  int block_size = 256;  // power of two, used when the DEM is created
};

struct DemImportReport {
  DemInfo dem;
  int64_t cells = 0;           // cells read from the sources
  int64_t blocks_written = 0;  // level 0 blocks stored
  int64_t bytes_stored = 0;    // compressed bytes of those blocks
  bool warped = false;         // a source was reprojected onto the store's CRS
};

class DemStore {
 public:
  explicit DemStore(Store& store);
  ~DemStore();

  // Imports `files` into one DEM in a single transaction; on any error nothing is stored.
  // Errors name the file: missing/unreadable, no CRS, no geotransform, rotated geotransform.
  Result<DemImportReport> Import(const std::vector<std::string>& files,
                                 const DemImportOptions& options);

  Result<std::vector<DemInfo>> List();
  // NotFound naming the DEM when there is none of that name.
  Result<DemInfo> Find(const std::string& name);
  Result<DemInfo> FindById(int64_t id);

  // Bilinear elevation at (x, y) in the store's CRS (GDAL's conventions, core/raster/bilinear.h).
  // InvalidArgument naming the point when it lies outside the DEM; NaN-valued cells around it
  // give NotFound ("no data at ...").
  Result<double> Sample(const DemInfo& dem, double x, double y);
  // The whole level-0 grid in memory (REQUIRES: it fits).
  Result<Grid> ReadGrid(const DemInfo& dem);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tinbase
