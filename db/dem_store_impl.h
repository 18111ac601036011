// DemStore's private parts, shared by the files that implement it (not for other callers):
// DemStore::Impl, and the helpers of more than one of those files. The implementation is split by
// concept: db/dem_store.cc (lookup, cache token), db/dem_blocks.cc (one block in and out of the
// table, the per-thread front cache), db/dem_import.cc (sheets into a mosaic), db/dem_overviews.cc
// (the levels above level 0) and db/dem_read.cc (sampling, windows, clips).
// Thread-safety: as DemStore's.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "core/raster/gdal_raster.h"
#include "core/raster/grid.h"
#include "db/dem_block_cache.h"
#include "db/dem_store.h"

namespace tinbase {
namespace dem_internal {

inline constexpr const char* kCacheTokenKey = "dem_cache_token";
inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Floor division for block indices left of or above the anchor (negative numerators).
inline int64_t FloorDiv(int64_t a, int64_t b) {
  const int64_t q = a / b;
  return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}

// "(x, y)" for messages.
std::string Point(double x, double y);
inline std::string Quoted(const std::string& name) { return "'" + name + "'"; }

// A fresh random cache token, never 0 (0 means "not read yet").
uint64_t NewToken();

// Levels until one block holds the whole level: each level halves the one below.
int LevelCount(const DemInfo& dem);

// One source raster of an import.
struct Sheet {
  GdalRaster raster;
  int64_t col0 = 0;  // the sheet's first column in the DEM's (final) level-0 grid
  int64_t row0 = 0;
};

// The cells [col_lo, col_hi] x [row_lo, row_hi] of a level grid.
struct CellRange {
  int64_t col_lo, col_hi, row_lo, row_hi;
};

// The blocks of a level a cell range touches.
struct BlockRange {
  int64_t bx_lo, bx_hi, by_lo, by_hi;
  int64_t Count() const { return (bx_hi - bx_lo + 1) * (by_hi - by_lo + 1); }
};

}  // namespace dem_internal

struct DemStore::Impl {
  explicit Impl(Store& s) : store(s) {}

  // A decoded block, or null when none is stored there (all nodata).
  using Block = DemBlockCache::Block;
  class CellReader;

  // The DEM of the row `where` selects after `bind` has bound its parameters, if any.
  Result<std::optional<DemInfo>> FindWhere(const std::string& where,
                                           const std::function<void(Statement&)>& bind);
  // A stored block as a window read lists it; `cells` is filled by LoadCells.
  struct StoredBlock {
    int64_t bx = 0, by = 0;
    float zmin = 0, zmax = 0;
    Block cells;
  };

  Result<Block> LoadBlock(const DemInfo& dem, int level, int64_t bx, int64_t by);
  // Through the thread's front cache and the process-wide cache; loads and caches on a miss.
  // The slot returned is owned by the front cache: valid until this thread's next lookup.
  Result<const Block*> FrontBlock(const DemInfo& dem, int level, int64_t bx, int64_t by);
  Result<Block> CachedBlock(const DemInfo& dem, int level, int64_t bx, int64_t by) {
    TB_ASSIGN_OR_RETURN(const Block* block, FrontBlock(dem, level, bx, by));
    return *block;
  }
  // The stored blocks of `level` in block columns [bx_lo, bx_hi] and rows [by_lo, by_hi], row by
  // row from the north west, with their extents but no cells.
  Result<std::vector<StoredBlock>> ListBlocks(const DemInfo& dem, int level, int64_t bx_lo,
                                              int64_t bx_hi, int64_t by_lo, int64_t by_hi);
  // The window's blocks from the process-wide cache alone (no SQL): true when every block
  // position of `br` is cached, either as a block or as known to hold none.
  bool CachedWindow(const DemInfo& dem, int level, const dem_internal::BlockRange& br,
                    std::vector<StoredBlock>* blocks);
  // Caches the positions of `br` that `stored` (ListBlocks' answer) lacks as holding no block.
  void CacheAbsent(const DemInfo& dem, int level, const dem_internal::BlockRange& br,
                   const std::vector<StoredBlock>& stored);
  // Sets `cells` of every block in `blocks` from the process-wide cache, fetching and decoding
  // the misses (on two threads when there are several) and caching them.
  Status LoadCells(const DemInfo& dem, int level, std::span<StoredBlock> blocks);
  // Reads the store's cache token (a process-local one when the store has none yet).
  Status RefreshToken();

  Result<DemImportReport> ImportInTransaction(const std::vector<std::string>& files,
                                              const DemImportOptions& options);
  // The sources of the DEM after the import: those stored for `existing` (if any), then one per
  // sheet, `files` and `source_crs` in the sheets' order.
  Result<nlohmann::json> SourcesAfter(const std::optional<DemInfo>& existing,
                                      const std::vector<dem_internal::Sheet>& sheets,
                                      const std::vector<std::string>& files,
                                      const std::vector<std::string>& source_crs);
  // Updates the row of `existing`, or inserts the row of a new DEM; returns the DEM's id.
  Result<int64_t> UpsertDem(const DemInfo& dem, const std::optional<DemInfo>& existing,
                            const nlohmann::json& sources);
  // The level-0 cells of block (bx, by): the stored block of `existing` (if any) with the sheets
  // over it laid on top (under the cells it has, with `keep_first`).
  Result<std::vector<float>> AssembleBlock(int64_t* infinite_cells, const DemInfo& dem,
                                           const std::optional<DemInfo>& existing,
                                           const std::vector<dem_internal::Sheet>& sheets,
                                           int64_t bx, int64_t by, bool keep_first);
  Result<Crs> StoreCrsFor(const GdalRaster& first);
  // Stores the block, or deletes it when it holds no data.
  Status WriteBlock(const DemInfo& dem, int level, int64_t bx, int64_t by,
                    const std::vector<float>& cells, DemImportReport* report);
  // Recomputes overview levels 1.. above the level-0 blocks `touched` ((by, bx) pairs); levels
  // the DEM did not have before (from `old_levels` on) are computed whole.
  Status UpdateOverviews(const DemInfo& dem, int old_levels,
                         std::set<std::pair<int64_t, int64_t>> touched, DemImportReport* report);
  // Into `grid`, reusing its memory.
  Status ReadCells(const DemInfo& dem, int level, const dem_internal::CellRange& range, Grid* grid);
  Status VisitBlocks(const DemInfo& dem, int level, const dem_internal::CellRange& range,
                     const std::function<Status(const DemBlock&)>& fn);

  // Runs the import's failure-injection hook, if any, after a block write, and reports progress.
  Status AfterBlockWrite() {
    ++blocks_done;
    if (progress && blocks_expected > 0)
      progress(std::min(1.0, static_cast<double>(blocks_done) / blocks_expected));
    return after_block_write ? after_block_write(blocks_done) : Status::Ok();
  }

  Store& store;
  uint64_t token = 0;  // the store's dem_cache_token as last read; 0: not read yet
  std::function<Status(int64_t)> after_block_write;  // of the import running
  std::function<void(double)> progress;              // of the import running
  int64_t blocks_done = 0;
  // Level 0's blocks and their overviews' (each level a quarter of the one below): 4/3 of them.
  double blocks_expected = 0;
};

}  // namespace tinbase
