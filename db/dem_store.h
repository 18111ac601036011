// DemStore: the blocked DEM database. Elevation grids cut into fixed-size float32 blocks,
// compressed, nodata kept as NaN, one row per block in `dem_blocks` (docs/format.md).
//
// Import reads any GDAL raster; rasters in another CRS than the store's are warped onto it with
// GDAL (bilinear). A store without a CRS adopts the first DEM's: a projected CRS as is, a
// geographic one replaced by the UTM zone of the raster's centre (GeographicLib). Sampling, window
// reads and ForEachBlock read only the blocks they need, through the process-wide cache of decoded
// blocks (db/dem_block_cache.h) with, for sampling, a per-thread front cache of the blocks used
// last (direct-mapped by position), so a warm sample takes no lock and no SQL; a warm window read
// finds its blocks in the cache without SQL, and a cold one decodes them on two threads. Every
// import gives the store a new cache token (meta `dem_cache_token`), so no block it replaced is
// served again from the cache; a DemStore picks up another process's import when it next looks a
// DEM up (Find, FindById, List). Several files imported into one DEM are sheets of a mosaic on one
// grid. Overview levels 1..levels-1 each halve the one below (a cell is the mean of the valid cells
// of the 2 x 2 below it) until one block holds the level; Import keeps them up to date, recomputing
// only the overview blocks above the level-0 blocks it wrote.
// Thread-safety: one DemStore per Store, one thread at a time; DemStores of several threads (each
// with its own Store) share the block cache safely.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
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

// Overview `level` of a DEM (0 = full resolution): its grid, and the column and row of that grid
// where block (0, 0) begins. Level L's cell k covers level-0 columns
// [block_col0 + k * 2^L, block_col0 + (k + 1) * 2^L) of the anchor, so levels stay aligned with the
// blocks below as the DEM grows. REQUIRES: 0 <= level < dem.levels.
struct DemLevel {
  GridGeometry geometry;
  int64_t block_col0 = 0;
  int64_t block_row0 = 0;
};
DemLevel LevelOf(const DemInfo& dem, int level);

// An axis-aligned box in the store's CRS.
struct DemBox {
  double min_x = 0;
  double min_y = 0;
  double max_x = 0;
  double max_y = 0;
};

// One stored block as ForEachBlock hands it out: valid only during the call.
struct DemBlock {
  int level = 0;
  int64_t bx = 0;
  int64_t by = 0;
  GridGeometry geometry;  // the block's block_size x block_size cells in the world
  float zmin = 0;         // of its valid cells
  float zmax = 0;
  const std::vector<float>* cells = nullptr;  // row-major, NaN = nodata
};

// What Clip wrote.
struct DemClip {
  int level = 0;          // the overview level the cells came from
  GridGeometry geometry;  // of the written raster
};

// The default DemImportOptions::max_cells: 2^34 cells, a 131072 x 131072 grid (64 GiB of float32).
inline constexpr int64_t kDefaultMaxDemImportCells = int64_t{1} << 34;

struct DemImportReport;

struct DemImportOptions {
  std::string name;      // DEM to create or extend; empty: the first file's stem
  int block_size = 256;  // power of two in [8, 4096], used when the DEM is created
  // Where sheets overlap (each other or the DEM being extended), the later sheet's valid cells
  // win; with keep_first, a later sheet only fills cells that are still nodata.
  bool keep_first = false;
  // At most this many cells are read from the sources (summed over the sheets); a larger import
  // is refused before anything is read or allocated, since a header can claim any size (a VRT
  // with no sources, a damaged GeoTIFF). 0: no limit (`dem import --force`).
  int64_t max_cells = kDefaultMaxDemImportCells;
  // Test seam for failure injection: called after every block written or deleted (level 0 and
  // overviews) with the count so far; a non-OK status aborts the import like a failed write
  // (the transaction rolls back, the store is unchanged) and Import returns it.
  std::function<Status(int64_t blocks_written)> after_block_write;
  // Called now and then with the fraction of the import done (by blocks written, the overviews
  // counted), from the calling thread; empty: not called. For progress bars.
  std::function<void(double fraction)> progress;
  // When set, an import into a DEM that surfaces are built on is allowed (`dem import
  // --update-surfaces`, db/edit/resurvey.h): it is called inside the import's transaction once
  // every block is written, with the import's report; reads through this DemStore then see the new
  // cells. A non-OK status rolls the whole import back and Import returns it.
  std::function<Status(const DemImportReport& report)> under_surfaces;
};

enum class DemSampling {
  kBilinear,  // GDAL's bilinear convention (core/raster/bilinear.h)
  kNearest,   // the value of the cell holding the point (on a shared edge: the east / south one)
};

struct DemImportReport {
  DemInfo dem;
  int64_t cells = 0;                    // cells read from the sources
  int64_t blocks_written = 0;           // level 0 blocks stored
  int64_t overview_blocks_written = 0;  // blocks of levels >= 1 stored (recomputed)
  int64_t bytes_stored = 0;             // compressed bytes of those blocks
  bool warped = false;                  // a source was reprojected onto the store's CRS
  int64_t infinite_cells = 0;           // source cells of +/-Inf, stored as nodata
  // The level-0 extent of the blocks written (a sheet's cells lie inside it), clipped to the DEM.
  DemBox written;
  // The DEM's grid before the import, when it existed.
  std::optional<GridGeometry> geometry_before;
};

// What is stored of one level of a DEM.
struct DemLevelStats {
  int64_t blocks = 0;  // stored blocks (blocks without data are not stored)
  int64_t bytes = 0;   // their compressed cells
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
  // Stored blocks and bytes of every level 0 .. max(dem.levels, 1) - 1, counted from the block
  // table (a level without blocks counts zero).
  Result<std::vector<DemLevelStats>> LevelStats(const DemInfo& dem);

  // Elevation at (x, y) in the store's CRS, bilinear (GDAL's conventions, core/raster/bilinear.h)
  // or nearest. InvalidArgument naming the point when it lies outside the DEM; NaN-valued cells
  // around it give NotFound ("no data at ..."); Corruption naming the block when it cannot be
  // decoded.
  Result<double> Sample(const DemInfo& dem, double x, double y,
                        DemSampling method = DemSampling::kBilinear);
  // The bilinear elevation at (x, y) as draping and re-triangulation take it: NaN means "no data
  // here" (the point is outside the DEM or its cells are nodata); an error means the read failed
  // (Corruption or IOError naming the block) and is never turned into NaN.
  Result<double> Elevation(const DemInfo& dem, double x, double y);
  // Samples many points in one call: out[i] = the elevation at (xs[i], ys[i]), NaN where the point
  // is outside the DEM or has no data. Points close together are fastest (the last block is kept
  // at hand). InvalidArgument when the spans differ in length; Corruption as Sample (out is then
  // partly written).
  Status SampleMany(const DemInfo& dem, std::span<const double> xs, std::span<const double> ys,
                    std::span<double> out, DemSampling method = DemSampling::kBilinear);
  // The decoded cells of block (bx, by) of `level` (block_size x block_size, row-major, NaN =
  // nodata; LevelOf gives where it lies) through the process-wide cache; null when no block is
  // stored there. Corruption naming the block when it cannot be decoded (whatever the codec says:
  // the store wrote the bytes, so bytes it cannot decode are damaged).
  Result<std::shared_ptr<const std::vector<float>>> ReadBlock(const DemInfo& dem, int level,
                                                              int64_t bx, int64_t by);
  // The whole level-0 grid in memory (REQUIRES: it fits).
  Result<Grid> ReadGrid(const DemInfo& dem);
  // The cells of overview `level` that intersect `box` (clipped to the DEM), NaN where no data.
  // InvalidArgument naming the DEM when the level does not exist or the box is empty, not finite
  // or does not overlap the DEM.
  Result<Grid> ReadWindow(const DemInfo& dem, const DemBox& box, int level = 0);
  // The same into `out`, reusing its memory (for callers reading window after window).
  Status ReadWindow(const DemInfo& dem, const DemBox& box, int level, Grid* out);
  // Calls `fn` for every stored block of `level` that intersects `box`, row by row from the north
  // west; blocks without data are not stored and not visited. Stops at and returns the first
  // error of `fn`; errors as ReadWindow.
  // The lowest and highest valid cell of `dem` (from the stored blocks' extents, no cell is
  // decoded); {0, 0} for a DEM without valid cells.
  Result<std::pair<double, double>> Relief(const DemInfo& dem);
  Status ForEachBlock(const DemInfo& dem, const DemBox& box, int level,
                      const std::function<Status(const DemBlock&)>& fn);
  // The finest level whose window of `box` holds at most `max_cells` cells (the coarsest if none
  // does): the sampling step of Clip and of `dem clip --faces`. Errors as ReadWindow.
  Result<int> ClipLevel(const DemInfo& dem, const DemBox& box, int64_t max_cells);
  // Writes the cells of `box` to a float32 GeoTIFF at `path` (nodata: the DEM's, else NaN) from
  // ClipLevel's level.
  // Errors as ReadWindow; IOError naming `path` when GDAL cannot write it.
  Result<DemClip> Clip(const DemInfo& dem, const DemBox& box, int64_t max_cells,
                       const std::string& path);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tinbase
