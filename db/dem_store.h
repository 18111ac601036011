// DemStore: the blocked DEM database. Elevation grids cut into fixed-size float32 blocks,
// compressed, nodata kept as NaN, one row per block in `dem_blocks` (docs/format.md).
//
// Import reads any GDAL raster; rasters in another CRS than the store's are warped onto it with
// GDAL (bilinear). A store without a CRS adopts the first DEM's: a projected CRS as is, a
// geographic one replaced by the UTM zone of the raster's centre (GeographicLib). Sampling reads
// only the blocks it needs, through a small cache of decoded blocks owned by the DemStore (cleared
// by every Import). Several files imported into one DEM are sheets of a mosaic on one grid.
// Thread-safety: one DemStore per Store, one thread at a time.
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
  // The level-0 column and row where block (0, 0) begins: the first sheet's origin. Blocks stay
  // anchored there when later sheets grow the DEM west or north (their bx, by go negative), so
  // extending a DEM writes only new and touched blocks. Block (bx, by) covers columns
  // [block_col0 + bx * block_size, block_col0 + (bx + 1) * block_size) and likewise rows.
  int64_t block_col0 = 0;
  int64_t block_row0 = 0;
};

struct DemImportOptions {
  std::string name;      // DEM to create or extend; empty: the first file's stem
  int block_size = 256;  // power of two in [8, 4096], used when the DEM is created
  // Where sheets overlap (each other or the DEM being extended), the later sheet's valid cells
  // win; with keep_first, a later sheet only fills cells that are still nodata.
  bool keep_first = false;
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
  // The files are sheets of one grid: the DEM named options.name is created, or extended when it
  // exists, to the union of its extent and the sheets'. Each sheet must line up with the DEM's
  // grid (same cell size, origin a whole number of cells away) once warped onto the store's CRS;
  // a sheet warped for an existing DEM is warped straight onto its grid. All-nodata blocks are
  // not stored. Returns what was written.
  // Errors name the file: missing (NotFound), unreadable or not a raster, no CRS, no
  // geotransform, rotated geotransform, grid not lining up (InvalidArgument); a block size that is
  // not a power of two in [8, 4096] or no files give InvalidArgument.
  // REQUIRES: no write transaction is open on the store.
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
