#include "db/dem_store.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <span>

#include "core/base/object_name.h"
#include "core/raster/bilinear.h"
#include "core/raster/block_codec.h"
#include "core/raster/gdal_raster.h"
#include "core/raster/grid.h"
#include "db/dem_block_cache.h"
#include "db/dem_import_checks.h"

namespace tinbase {

namespace {

constexpr int kMinBlockSize = 8;
constexpr int kMaxBlockSize = 4096;
constexpr const char* kCacheTokenKey = "dem_cache_token";
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Floor division for block indices left of or above the anchor (negative numerators).
int64_t FloorDiv(int64_t a, int64_t b) {
  const int64_t q = a / b;
  return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}

std::string Point(double x, double y) {
  char buf[80];
  std::snprintf(buf, sizeof buf, "(%.10g, %.10g)", x, y);
  return buf;
}

std::string Quoted(const std::string& name) { return "'" + name + "'"; }

// A stored block that does not decode is damaged, whatever the codec reported (an unknown codec
// number is InvalidArgument to the codec, but here the store wrote it): Corruption naming the
// block, so that no caller can take it for nodata or for the user's mistake.
Status DamagedBlock(const Status& decode, const DemInfo& dem, int level, int64_t bx, int64_t by) {
  return Status::Corruption("DEM " + Quoted(dem.name) + ", level " + std::to_string(level) +
                            " block (" + std::to_string(bx) + ", " + std::to_string(by) +
                            ") is damaged: " + decode.message());
}

// A whole number of cells `offset / cell` away, or nullopt when the grids do not line up. The
// tolerance (1e-6 of a cell) absorbs the round-off of origins written as decimal text.
std::optional<int64_t> WholeCells(double offset, double cell) {
  const double cells = offset / cell;
  const double rounded = std::round(cells);
  if (std::abs(cells - rounded) > 1e-6) return std::nullopt;
  return static_cast<int64_t>(rounded);
}

bool SameCellSize(double a, double b) { return std::abs(a - b) <= 1e-9 * std::abs(b); }

struct Sheet {
  GdalRaster raster;
  int64_t col0 = 0;  // the sheet's first column in the DEM's (final) level-0 grid
  int64_t row0 = 0;
};

// Levels until one block holds the whole level: each level halves the one below.
int LevelCount(const DemInfo& dem) {
  constexpr int kMaxLevels = 31;
  for (int level = 0; level + 1 < kMaxLevels; ++level) {
    const DemLevel lv = LevelOf(dem, level);
    const int64_t b = dem.block_size;
    const bool one_column =
        FloorDiv(-lv.block_col0, b) == FloorDiv(lv.geometry.width - 1 - lv.block_col0, b);
    const bool one_row =
        FloorDiv(-lv.block_row0, b) == FloorDiv(lv.geometry.height - 1 - lv.block_row0, b);
    if (one_column && one_row) return level + 1;
  }
  return kMaxLevels;
}

// The cells [col_lo, col_hi] x [row_lo, row_hi] of a level grid.
struct CellRange {
  int64_t col_lo, col_hi, row_lo, row_hi;
};

// The cells of `g` that intersect `box`; InvalidArgument naming the DEM when there are none.
Result<CellRange> CellsIn(const GridGeometry& g, const DemBox& box, const std::string& dem) {
  const std::string where =
      "box " + Point(box.min_x, box.min_y) + " - " + Point(box.max_x, box.max_y);
  if (!std::isfinite(box.min_x) || !std::isfinite(box.min_y) || !std::isfinite(box.max_x) ||
      !std::isfinite(box.max_y) || box.min_x > box.max_x || box.min_y > box.max_y)
    return Status::InvalidArgument(where + " is not a box");
  if (box.max_x < g.MinX() || box.min_x > g.MaxX() || box.max_y < g.MinY() || box.min_y > g.MaxY())
    return Status::InvalidArgument(where + " does not overlap DEM " + Quoted(dem));
  const auto lo = [](double v) { return static_cast<int64_t>(std::floor(v)); };
  // A box edge on a cell edge does not take in the cell beyond it; a zero-width box takes one.
  const auto hi = [](double v, int64_t low) {
    return std::max(low, static_cast<int64_t>(std::ceil(v)) - 1);
  };
  CellRange r;
  r.col_lo = lo((box.min_x - g.origin_x) / g.cell_x);
  r.col_hi = hi((box.max_x - g.origin_x) / g.cell_x, r.col_lo);
  r.row_lo = lo((box.max_y - g.origin_y) / g.cell_y);
  r.row_hi = hi((box.min_y - g.origin_y) / g.cell_y, r.row_lo);
  r.col_lo = std::clamp<int64_t>(r.col_lo, 0, g.width - 1);
  r.col_hi = std::clamp<int64_t>(r.col_hi, 0, g.width - 1);
  r.row_lo = std::clamp<int64_t>(r.row_lo, 0, g.height - 1);
  r.row_hi = std::clamp<int64_t>(r.row_hi, 0, g.height - 1);
  return r;
}

// The blocks of a level a cell range touches.
struct BlockRange {
  int64_t bx_lo, bx_hi, by_lo, by_hi;
  int64_t Count() const { return (bx_hi - bx_lo + 1) * (by_hi - by_lo + 1); }
};

// The parent cells of four child blocks (nullptr: not stored): each the mean of the valid cells of
// the 2 x 2 below it. children[dy * 2 + dx] is child (2 bx + dx, 2 by + dy).
std::vector<float> Downsample(const std::vector<float>* const children[4], int64_t b) {
  std::vector<float> parent(static_cast<size_t>(b * b), kNaN);
  const int64_t half = b / 2;
  for (int64_t r = 0; r < b; ++r) {
    for (int64_t c = 0; c < b; ++c) {
      const std::vector<float>* child = children[(r / half) * 2 + c / half];
      if (child == nullptr) continue;
      const int64_t cr = (r % half) * 2;
      const int64_t cc = (c % half) * 2;
      double sum = 0;
      int valid = 0;
      for (int64_t dr = 0; dr < 2; ++dr)
        for (int64_t dc = 0; dc < 2; ++dc) {
          const float v = (*child)[static_cast<size_t>((cr + dr) * b + cc + dc)];
          if (std::isnan(v)) continue;
          sum += v;
          ++valid;
        }
      if (valid > 0) parent[static_cast<size_t>(r * b + c)] = static_cast<float>(sum / valid);
    }
  }
  return parent;
}

constexpr const char* kDemColumns =
    "SELECT id, name, crs_wkt, origin_x, origin_y, cell_x, cell_y, width, height, block_size, "
    "nodata, levels, block_col0, block_row0 FROM dems ";

DemInfo InfoFromRow(const Statement& row) {
  DemInfo info;
  info.id = row.ColumnInt(0);
  info.name = row.ColumnText(1);
  info.crs_wkt = row.ColumnText(2);
  info.geometry = GridGeometry{row.ColumnDouble(3), row.ColumnDouble(4), row.ColumnDouble(5),
                               row.ColumnDouble(6), row.ColumnInt(7),    row.ColumnInt(8)};
  info.block_size = static_cast<int>(row.ColumnInt(9));
  if (!row.ColumnIsNull(10)) info.nodata = row.ColumnDouble(10);
  info.levels = static_cast<int>(row.ColumnInt(11));
  info.block_col0 = row.ColumnInt(12);
  info.block_row0 = row.ColumnInt(13);
  return info;
}

}  // namespace

DemLevel LevelOf(const DemInfo& dem, int level) {
  const int64_t f = int64_t{1} << level;
  const GridGeometry& g = dem.geometry;
  // The level's first and last cells, counted from the anchor.
  const int64_t c0 = FloorDiv(-dem.block_col0, f);
  const int64_t c1 = FloorDiv(g.width - 1 - dem.block_col0, f);
  const int64_t r0 = FloorDiv(-dem.block_row0, f);
  const int64_t r1 = FloorDiv(g.height - 1 - dem.block_row0, f);
  DemLevel out;
  out.geometry.origin_x = g.origin_x + static_cast<double>(dem.block_col0 + c0 * f) * g.cell_x;
  out.geometry.origin_y = g.origin_y + static_cast<double>(dem.block_row0 + r0 * f) * g.cell_y;
  out.geometry.cell_x = g.cell_x * static_cast<double>(f);
  out.geometry.cell_y = g.cell_y * static_cast<double>(f);
  out.geometry.width = c1 - c0 + 1;
  out.geometry.height = r1 - r0 + 1;
  out.block_col0 = -c0;
  out.block_row0 = -r0;
  return out;
}

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
  bool CachedWindow(const DemInfo& dem, int level, const BlockRange& br,
                    std::vector<StoredBlock>* blocks);
  // Caches the positions of `br` that `stored` (ListBlocks' answer) lacks as holding no block.
  void CacheAbsent(const DemInfo& dem, int level, const BlockRange& br,
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
                                      const std::vector<Sheet>& sheets,
                                      const std::vector<std::string>& files,
                                      const std::vector<std::string>& source_crs);
  // Updates the row of `existing`, or inserts the row of a new DEM; returns the DEM's id.
  Result<int64_t> UpsertDem(const DemInfo& dem, const std::optional<DemInfo>& existing,
                            const nlohmann::json& sources);
  // The level-0 cells of block (bx, by): the stored block of `existing` (if any) with the sheets
  // over it laid on top (under the cells it has, with `keep_first`).
  Result<std::vector<float>> AssembleBlock(int64_t* infinite_cells, const DemInfo& dem,
                                           const std::optional<DemInfo>& existing,
                                           const std::vector<Sheet>& sheets, int64_t bx, int64_t by,
                                           bool keep_first);
  Result<Crs> StoreCrsFor(const GdalRaster& first);
  // Stores the block, or deletes it when it holds no data.
  Status WriteBlock(const DemInfo& dem, int level, int64_t bx, int64_t by,
                    const std::vector<float>& cells, DemImportReport* report);
  // Recomputes overview levels 1.. above the level-0 blocks `touched` ((by, bx) pairs); levels
  // the DEM did not have before (from `old_levels` on) are computed whole.
  Status UpdateOverviews(const DemInfo& dem, int old_levels,
                         std::set<std::pair<int64_t, int64_t>> touched, DemImportReport* report);
  // Into `grid`, reusing its memory.
  Status ReadCells(const DemInfo& dem, int level, const CellRange& range, Grid* grid);
  Status VisitBlocks(const DemInfo& dem, int level, const CellRange& range,
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

namespace {

// A fresh random cache token, never 0 (0 means "not read yet"). Drawn from the OS each time:
// a generator seeded once would hand a forked child the parent's next tokens, and two stores
// with one token share cache entries.
uint64_t NewToken() {
  std::random_device os;
  uint64_t t = 0;
  while (t == 0) t = os() ^ (static_cast<uint64_t>(os()) << 32);
  return t;
}

// The blocks this thread used last, direct-mapped by block position (an 8 x 8 neighbourhood of
// blocks never collides), so a warm sample takes no lock, no SQL and no reference count. It holds
// at most kFrontBytes (and at least kMinFrontSlots blocks) per thread beyond the process-wide
// cache's limit.
struct FrontEntry {
  DemBlockKey key;
  DemBlockCache::Block block;
  bool used = false;
};
constexpr size_t kMaxFrontSlots = 64;
constexpr size_t kMinFrontSlots = 4;
constexpr size_t kFrontBytes = size_t{16} << 20;
thread_local std::array<FrontEntry, kMaxFrontSlots> t_front;

FrontEntry& FrontSlot(const DemBlockKey& key, int block_size) {
  const size_t block_bytes = static_cast<size_t>(block_size) * block_size * sizeof(float);
  const size_t slots =
      std::clamp(std::bit_floor(kFrontBytes / block_bytes), kMinFrontSlots, kMaxFrontSlots);
  const int side_bits = (std::countr_zero(slots) + 1) / 2;  // 8 x 8 for 64 slots
  const auto index = static_cast<size_t>(key.bx + (key.by << side_bits) + key.level * 7);
  return t_front[index & (slots - 1)];
}

}  // namespace

Status DemStore::Impl::RefreshToken() {
  TB_ASSIGN_OR_RETURN(std::optional<std::string> value, store.GetMeta(kCacheTokenKey));
  uint64_t t = 0;
  if (value) t = std::strtoull(value->c_str(), nullptr, 10);
  // A store no import of this version has touched: a token of this DemStore alone, never shared.
  if (t == 0) t = token != 0 ? token : NewToken();
  token = t;
  return Status::Ok();
}

// Cells of one level by (col, row), through the blocks: the block of the last cell is kept, so
// the four cells of a bilinear sample, and nearby points, cost one block lookup.
class DemStore::Impl::CellReader {
 public:
  CellReader(Impl& impl, const DemInfo& dem, int level)
      : impl_(impl),
        dem_(dem),
        level_(level),
        shift_(std::countr_zero(static_cast<unsigned>(dem.block_size))),
        mask_(dem.block_size - 1) {
    const DemLevel lv = LevelOf(dem, level);
    col0_ = lv.block_col0;
    row0_ = lv.block_row0;
  }

  // REQUIRES: no other block lookup on this thread while the reader is in use (the cells it
  // points at belong to the thread's front cache).
  float operator()(int64_t col, int64_t row) {
    const int64_t c = col - col0_;
    const int64_t r = row - row0_;
    // Block sizes are powers of two: an arithmetic shift is floor division, also west of the
    // anchor.
    const int64_t bx = c >> shift_;
    const int64_t by = r >> shift_;
    if (bx != bx_ || by != by_) Switch(bx, by);
    if (cells_ == nullptr) return kNaN;
    return cells_[static_cast<size_t>(((r & mask_) << shift_) + (c & mask_))];
  }

  const Status& status() const { return status_; }

 private:
  void Switch(int64_t bx, int64_t by) {
    auto block = impl_.FrontBlock(dem_, level_, bx, by);
    if (!block.ok()) {
      if (status_.ok()) status_ = block.status();
      bx_ = by_ = std::numeric_limits<int64_t>::min();
      cells_ = nullptr;
      return;
    }
    bx_ = bx;
    by_ = by;
    cells_ = **block ? (**block)->data() : nullptr;
  }

  Impl& impl_;
  const DemInfo& dem_;
  int level_;
  int shift_;
  int64_t mask_;
  int64_t col0_ = 0;
  int64_t row0_ = 0;
  int64_t bx_ = std::numeric_limits<int64_t>::min();
  int64_t by_ = std::numeric_limits<int64_t>::min();
  const float* cells_ = nullptr;
  Status status_;
};

Result<std::optional<DemInfo>> DemStore::Impl::FindWhere(
    const std::string& where, const std::function<void(Statement&)>& bind) {
  TB_ASSIGN_OR_RETURN(Statement * stmt, store.db().Cached(kDemColumns + where));
  bind(*stmt);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  std::optional<DemInfo> info;
  if (row) info = InfoFromRow(*stmt);
  stmt->Reset();
  return info;
}

Result<DemStore::Impl::Block> DemStore::Impl::LoadBlock(const DemInfo& dem, int level, int64_t bx,
                                                        int64_t by) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("SELECT codec, data FROM dem_blocks "
                                        "WHERE dem = ? AND level = ? AND bx = ? AND by = ?"));
  stmt->Bind(1, dem.id).Bind(2, static_cast<int64_t>(level)).Bind(3, bx).Bind(4, by);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  if (!row) {
    stmt->Reset();
    return Block();
  }
  size_t size = 0;
  const uint8_t* data = stmt->ColumnBlob(1, &size);
  auto cells = DecodeBlock(static_cast<int>(stmt->ColumnInt(0)), std::span(data, size),
                           static_cast<size_t>(dem.block_size) * dem.block_size);
  stmt->Reset();
  if (!cells.ok()) return DamagedBlock(cells.status(), dem, level, bx, by);
  return Block(std::make_shared<const std::vector<float>>(std::move(cells).value()));
}

Result<const DemStore::Impl::Block*> DemStore::Impl::FrontBlock(const DemInfo& dem, int level,
                                                                int64_t bx, int64_t by) {
  if (token == 0) TB_RETURN_IF_ERROR(RefreshToken());
  const DemBlockKey key{token, dem.id, level, bx, by};
  FrontEntry& slot = FrontSlot(key, dem.block_size);
  if (slot.used && slot.key == key) return &slot.block;
  Block block;
  DemBlockCache& cache = DemBlockCache::Instance();
  if (!cache.Lookup(key, &block)) {
    TB_ASSIGN_OR_RETURN(block, LoadBlock(dem, level, bx, by));
    cache.Insert(key, block);
  }
  slot = FrontEntry{key, std::move(block), true};
  return &slot.block;
}

Result<Crs> DemStore::Impl::StoreCrsFor(const GdalRaster& first) {
  TB_ASSIGN_OR_RETURN(std::optional<Crs> crs, store.GetCrs());
  if (crs) return std::move(*crs);
  Crs adopted = first.crs();
  if (adopted.IsGeographic()) {
    const GridGeometry& g = first.geometry();
    auto utm = Crs::UtmFor((g.MinX() + g.MaxX()) / 2, (g.MinY() + g.MaxY()) / 2);
    if (!utm.ok()) return utm.status().WithContext(first.path());
    adopted = std::move(utm).value();
  }
  TB_RETURN_IF_ERROR(store.SetCrs(adopted));
  return adopted;
}

Status DemStore::Impl::WriteBlock(const DemInfo& dem, int level, int64_t bx, int64_t by,
                                  const std::vector<float>& cells, DemImportReport* report) {
  float zmin = std::numeric_limits<float>::infinity();
  float zmax = -zmin;
  for (float v : cells) {
    if (std::isnan(v)) continue;
    zmin = std::min(zmin, v);
    zmax = std::max(zmax, v);
  }
  if (zmin > zmax) {  // all nodata: not stored, a missing block reads as NaN
    TB_ASSIGN_OR_RETURN(Statement * del,
                        store.db().Cached("DELETE FROM dem_blocks "
                                          "WHERE dem = ? AND level = ? AND bx = ? AND by = ?"));
    del->Bind(1, dem.id).Bind(2, static_cast<int64_t>(level)).Bind(3, bx).Bind(4, by);
    TB_RETURN_IF_ERROR(del->Run());
    return AfterBlockWrite();
  }
  const std::vector<uint8_t> bytes = EncodeBlock(cells, dem.block_size);
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      store.db().Cached("INSERT INTO dem_blocks(dem, level, bx, by, codec, data, zmin, zmax) "
                        "VALUES (?, ?, ?, ?, ?, ?, ?, ?) "
                        "ON CONFLICT (dem, level, bx, by) DO UPDATE SET "
                        "codec = excluded.codec, data = excluded.data, "
                        "zmin = excluded.zmin, zmax = excluded.zmax"));
  stmt->Bind(1, dem.id).Bind(2, static_cast<int64_t>(level)).Bind(3, bx).Bind(4, by);
  stmt->Bind(5, static_cast<int64_t>(BlockCodec::kPlanarBloscZstd));
  stmt->BindBlob(6, bytes.data(), bytes.size());
  stmt->Bind(7, static_cast<double>(zmin)).Bind(8, static_cast<double>(zmax));
  TB_RETURN_IF_ERROR(stmt->Run());
  if (level == 0) {
    ++report->blocks_written;
    report->bytes_stored += static_cast<int64_t>(bytes.size());
  } else {
    ++report->overview_blocks_written;
  }
  return AfterBlockWrite();
}

Status DemStore::Impl::UpdateOverviews(const DemInfo& dem, int old_levels,
                                       std::set<std::pair<int64_t, int64_t>> touched,
                                       DemImportReport* report) {
  for (int level = 1; level < dem.levels; ++level) {
    if (level >= old_levels) {  // a new level: every block of the level below has a parent here
      touched.clear();
      TB_ASSIGN_OR_RETURN(Statement * all, store.db().Cached("SELECT bx, by FROM dem_blocks "
                                                             "WHERE dem = ? AND level = ?"));
      all->Bind(1, dem.id).Bind(2, static_cast<int64_t>(level - 1));
      for (;;) {
        auto row = all->Step();
        if (!row.ok() || !*row) {
          all->Reset();
          TB_RETURN_IF_ERROR(row.status());
          break;
        }
        touched.emplace(all->ColumnInt(1), all->ColumnInt(0));
      }
    }
    std::set<std::pair<int64_t, int64_t>> parents;
    for (const auto& [by, bx] : touched) parents.emplace(FloorDiv(by, 2), FloorDiv(bx, 2));
    for (const auto& [by, bx] : parents) {
      Block children[4];
      const std::vector<float>* cells[4];
      for (int i = 0; i < 4; ++i) {
        TB_ASSIGN_OR_RETURN(children[i], LoadBlock(dem, level - 1, 2 * bx + i % 2, 2 * by + i / 2));
        cells[i] = children[i].get();
      }
      TB_RETURN_IF_ERROR(WriteBlock(dem, level, bx, by, Downsample(cells, dem.block_size), report));
    }
    touched = std::move(parents);
  }
  return Status::Ok();
}

namespace {

// Every file opened, before anything is written, so the common failures cost nothing.
Result<std::vector<GdalRaster>> OpenRasters(const std::vector<std::string>& files) {
  std::vector<GdalRaster> rasters;
  for (const std::string& file : files) {
    TB_ASSIGN_OR_RETURN(GdalRaster raster, GdalRaster::Open(file));
    rasters.push_back(std::move(raster));
  }
  return rasters;
}

// The sheets of an import on one grid (the existing DEM's, else the first sheet's), each at its
// first cell in that grid, before the DEM's extent is known.
struct Placement {
  std::vector<Sheet> sheets;
  std::vector<std::string> source_crs;  // as the files declare it, before any warp
  GridGeometry grid;
  bool warped = false;  // some sheet was warped to the store's CRS
  int64_t cells = 0;    // the sheets' cells
};

// Warps every raster not in `crs` and places it on the grid; InvalidArgument naming the file
// whose cell size differs from the grid's or whose origin does not lie on it.
// REQUIRES: `rasters` is not empty.
Result<Placement> PlaceSheets(std::vector<GdalRaster> rasters, const Crs& crs,
                              const std::optional<DemInfo>& existing, const std::string& name) {
  Placement out;
  std::optional<GridGeometry> grid;
  if (existing) grid = existing->geometry;
  for (GdalRaster& raster : rasters) {
    out.source_crs.push_back(raster.crs().Label());
    if (!raster.crs().IsSame(crs)) {
      TB_ASSIGN_OR_RETURN(raster, raster.WarpTo(crs, grid ? &*grid : nullptr));
      out.warped = true;
    }
    const GridGeometry& g = raster.geometry();
    if (!grid) grid = g;
    if (!SameCellSize(g.cell_x, grid->cell_x) || !SameCellSize(g.cell_y, grid->cell_y))
      return Status::InvalidArgument(raster.path() + ": cell size " + Point(g.cell_x, g.cell_y) +
                                     " differs from DEM " + Quoted(name) + "'s " +
                                     Point(grid->cell_x, grid->cell_y));
    const auto col0 = WholeCells(g.origin_x - grid->origin_x, grid->cell_x);
    const auto row0 = WholeCells(g.origin_y - grid->origin_y, grid->cell_y);
    if (!col0 || !row0)
      return Status::InvalidArgument(raster.path() + ": origin " + Point(g.origin_x, g.origin_y) +
                                     " does not lie on the grid of DEM " + Quoted(name));
    out.sheets.push_back(Sheet{raster, *col0, *row0});
    out.cells += g.CellCount();
  }
  out.grid = *grid;
  return out;
}

// The DEM after the import: the union of `existing` (if any) and the sheets, on `grid`, anchored
// where it was (a new DEM at its first sheet), with its levels. Shifts the sheets' first cells to
// the union's grid.
DemInfo DemOverSheets(const std::optional<DemInfo>& existing, const std::string& name,
                      const Crs& crs, const GridGeometry& grid,
                      const std::optional<double>& first_nodata, int block_size,
                      std::vector<Sheet>& sheets) {
  // The union of the DEM and the sheets, in cells of the grid placed so far.
  int64_t min_col = 0, min_row = 0;
  int64_t max_col = existing ? existing->geometry.width : 0;
  int64_t max_row = existing ? existing->geometry.height : 0;
  for (const Sheet& s : sheets) {
    min_col = std::min(min_col, s.col0);
    min_row = std::min(min_row, s.row0);
    max_col = std::max(max_col, s.col0 + s.raster.geometry().width);
    max_row = std::max(max_row, s.row0 + s.raster.geometry().height);
  }
  for (Sheet& s : sheets) {
    s.col0 -= min_col;
    s.row0 -= min_row;
  }
  DemInfo dem = existing.value_or(DemInfo{});
  dem.name = name;
  dem.crs_wkt = crs.Wkt();
  dem.geometry = grid;
  dem.geometry.origin_x = grid.origin_x + static_cast<double>(min_col) * grid.cell_x;
  dem.geometry.origin_y = grid.origin_y + static_cast<double>(min_row) * grid.cell_y;
  dem.geometry.width = max_col - min_col;
  dem.geometry.height = max_row - min_row;
  if (existing) {
    dem.block_col0 = existing->block_col0 - min_col;
    dem.block_row0 = existing->block_row0 - min_row;
  } else {
    dem.block_size = block_size;
    dem.nodata = first_nodata;
    dem.block_col0 = sheets.front().col0;
    dem.block_row0 = sheets.front().row0;
  }
  dem.levels = LevelCount(dem);
  return dem;
}

// The level-0 blocks any sheet touches, as (by, bx): row-major, as GDAL reads best.
std::set<std::pair<int64_t, int64_t>> BlocksUnder(const DemInfo& dem,
                                                  const std::vector<Sheet>& sheets) {
  const int64_t b = dem.block_size;
  std::set<std::pair<int64_t, int64_t>> touched;
  for (const Sheet& s : sheets) {
    const GridGeometry& g = s.raster.geometry();
    for (int64_t by = FloorDiv(s.row0 - dem.block_row0, b);
         by <= FloorDiv(s.row0 + g.height - 1 - dem.block_row0, b); ++by)
      for (int64_t bx = FloorDiv(s.col0 - dem.block_col0, b);
           bx <= FloorDiv(s.col0 + g.width - 1 - dem.block_col0, b); ++bx)
        touched.emplace(by, bx);
  }
  return touched;
}

}  // namespace

Result<nlohmann::json> DemStore::Impl::SourcesAfter(const std::optional<DemInfo>& existing,
                                                    const std::vector<Sheet>& sheets,
                                                    const std::vector<std::string>& files,
                                                    const std::vector<std::string>& source_crs) {
  nlohmann::json sources = nlohmann::json::array();
  if (existing) {
    TB_ASSIGN_OR_RETURN(Statement * get,
                        store.db().Cached("SELECT sources FROM dems WHERE id = ?"));
    get->Bind(1, existing->id);
    TB_ASSIGN_OR_RETURN(bool row, get->Step());
    if (row) sources = nlohmann::json::parse(get->ColumnText(0), nullptr, false);
    get->Reset();
  }
  for (size_t i = 0; i < sheets.size(); ++i) {
    const GridGeometry& g = sheets[i].raster.geometry();
    sources.push_back({{"file", files[i]},
                       {"crs", source_crs[i]},
                       {"warped", sheets[i].raster.warped()},
                       {"origin_x", g.origin_x},
                       {"origin_y", g.origin_y},
                       {"width", g.width},
                       {"height", g.height}});
  }
  return sources;
}

Result<int64_t> DemStore::Impl::UpsertDem(const DemInfo& dem,
                                          const std::optional<DemInfo>& existing,
                                          const nlohmann::json& sources) {
  // The geometry, anchor, sources and levels change with every import; the rest is set at
  // creation.
  Statement* upsert = nullptr;
  if (existing) {
    TB_ASSIGN_OR_RETURN(upsert, store.db().Cached("UPDATE dems SET origin_x = ?1, origin_y = ?2, "
                                                  "width = ?3, height = ?4, sources = ?5, "
                                                  "levels = ?6, block_col0 = ?7, block_row0 = ?8 "
                                                  "WHERE id = ?9 RETURNING id"));
    upsert->Bind(9, existing->id);
  } else {
    TB_ASSIGN_OR_RETURN(upsert,
                        store.db().Cached("INSERT INTO dems(origin_x, origin_y, width, height, "
                                          "sources, levels, block_col0, block_row0, name, "
                                          "crs_wkt, cell_x, cell_y, block_size, nodata) "
                                          "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, "
                                          "?12, ?13, ?14) RETURNING id"));
    upsert->Bind(9, dem.name).Bind(10, dem.crs_wkt).Bind(11, dem.geometry.cell_x);
    upsert->Bind(12, dem.geometry.cell_y).Bind(13, static_cast<int64_t>(dem.block_size));
    if (dem.nodata) {
      upsert->Bind(14, *dem.nodata);
    } else {
      upsert->BindNull(14);
    }
  }
  upsert->Bind(1, dem.geometry.origin_x).Bind(2, dem.geometry.origin_y);
  upsert->Bind(3, dem.geometry.width).Bind(4, dem.geometry.height).Bind(5, sources.dump());
  upsert->Bind(6, static_cast<int64_t>(dem.levels));
  upsert->Bind(7, dem.block_col0).Bind(8, dem.block_row0);
  return RunReturningId(*upsert);
}

Result<std::vector<float>> DemStore::Impl::AssembleBlock(int64_t* infinite_cells,
                                                         const DemInfo& dem,
                                                         const std::optional<DemInfo>& existing,
                                                         const std::vector<Sheet>& sheets,
                                                         int64_t bx, int64_t by, bool keep_first) {
  const int64_t b = dem.block_size;
  std::vector<float> cells(static_cast<size_t>(b * b), kNaN);
  if (existing) {
    TB_ASSIGN_OR_RETURN(Block old, LoadBlock(*existing, 0, bx, by));
    if (old) cells = *old;
  }
  const int64_t col = dem.block_col0 + bx * b;  // the block's first cell in the DEM grid
  const int64_t row = dem.block_row0 + by * b;
  for (const Sheet& s : sheets) {
    const GridGeometry& g = s.raster.geometry();
    if (col >= s.col0 + g.width || col + b <= s.col0 || row >= s.row0 + g.height ||
        row + b <= s.row0)
      continue;
    TB_ASSIGN_OR_RETURN(std::vector<float> window,
                        s.raster.ReadWindow(col - s.col0, row - s.row0, b, b));
    for (size_t i = 0; i < cells.size(); ++i) {
      // An infinite cell holds no elevation: it is nodata, counted so the import can say so.
      if (std::isinf(window[i])) {
        ++*infinite_cells;
        continue;
      }
      if (std::isnan(window[i]) || (keep_first && !std::isnan(cells[i]))) continue;
      cells[i] = window[i];
    }
  }
  return cells;
}

// The level-0 extent of blocks `touched` (by, bx), clipped to the DEM's grid.
DemBox WrittenBox(const DemInfo& dem, const std::set<std::pair<int64_t, int64_t>>& touched) {
  const GridGeometry& g = dem.geometry;
  const int64_t b = dem.block_size;
  int64_t c0 = g.width, c1 = 0, r0 = g.height, r1 = 0;
  for (const auto& [by, bx] : touched) {
    c0 = std::min(c0, dem.block_col0 + bx * b);
    c1 = std::max(c1, dem.block_col0 + (bx + 1) * b);
    r0 = std::min(r0, dem.block_row0 + by * b);
    r1 = std::max(r1, dem.block_row0 + (by + 1) * b);
  }
  c0 = std::max<int64_t>(c0, 0), r0 = std::max<int64_t>(r0, 0);
  c1 = std::min(c1, g.width), r1 = std::min(r1, g.height);
  if (c0 >= c1 || r0 >= r1) return {};
  const double xa = g.origin_x + static_cast<double>(c0) * g.cell_x;
  const double xb = g.origin_x + static_cast<double>(c1) * g.cell_x;
  const double ya = g.origin_y + static_cast<double>(r0) * g.cell_y;
  const double yb = g.origin_y + static_cast<double>(r1) * g.cell_y;
  return {std::min(xa, xb), std::min(ya, yb), std::max(xa, xb), std::max(ya, yb)};
}

Result<DemImportReport> DemStore::Impl::ImportInTransaction(const std::vector<std::string>& files,
                                                            const DemImportOptions& options) {
  TB_ASSIGN_OR_RETURN(std::vector<GdalRaster> rasters, OpenRasters(files));
  const std::string name =
      options.name.empty() ? std::filesystem::path(files.front()).stem().string() : options.name;
  if (name.empty()) return Status::InvalidArgument(files.front() + ": no name for the DEM");
  TB_RETURN_IF_ERROR(CheckObjectName("DEM", name));

  DemImportReport report;
  TB_ASSIGN_OR_RETURN(std::optional<DemInfo> existing,
                      FindWhere("WHERE name = ?", [&](Statement& st) { st.Bind(1, name); }));
  if (existing && !options.under_surfaces)
    TB_RETURN_IF_ERROR(RefuseImportUnderSurfaces(store, *existing));
  if (existing) report.geometry_before = existing->geometry;
  TB_RETURN_IF_ERROR(CheckDemImportCells(rasters, options.max_cells));
  TB_ASSIGN_OR_RETURN(Crs crs, StoreCrsFor(rasters.front()));
  const std::optional<double> first_nodata = rasters.front().nodata();
  TB_ASSIGN_OR_RETURN(Placement placed, PlaceSheets(std::move(rasters), crs, existing, name));
  report.warped = placed.warped;
  report.cells = placed.cells;
  if (options.max_cells > 0 && placed.cells > options.max_cells)
    return TooManyDemImportCells(
        "the rasters warped onto the store's CRS have " + std::to_string(placed.cells) + " cells",
        options.max_cells);
  std::vector<Sheet>& sheets = placed.sheets;
  DemInfo dem =
      DemOverSheets(existing, name, crs, placed.grid, first_nodata, options.block_size, sheets);
  const int old_levels = existing ? existing->levels : 1;

  TB_ASSIGN_OR_RETURN(const nlohmann::json sources,
                      SourcesAfter(existing, sheets, files, placed.source_crs));
  TB_ASSIGN_OR_RETURN(dem.id, UpsertDem(dem, existing, sources));

  // Blocks touched by any sheet, each assembled once from the stored block and the sheets over it.
  const std::set<std::pair<int64_t, int64_t>> touched = BlocksUnder(dem, sheets);
  blocks_expected = static_cast<double>(touched.size()) * 4 / 3;
  for (const auto& [by, bx] : touched) {
    TB_ASSIGN_OR_RETURN(
        std::vector<float> cells,
        AssembleBlock(&report.infinite_cells, dem, existing, sheets, bx, by, options.keep_first));
    TB_RETURN_IF_ERROR(WriteBlock(dem, 0, bx, by, cells, &report));
  }
  TB_RETURN_IF_ERROR(UpdateOverviews(dem, old_levels, touched, &report));
  report.dem = dem;
  report.written = WrittenBox(dem, touched);
  return report;
}

DemStore::DemStore(Store& store) : impl_(std::make_unique<Impl>(store)) {}
DemStore::~DemStore() = default;

Result<DemImportReport> DemStore::Import(const std::vector<std::string>& files,
                                         const DemImportOptions& options) {
  if (files.empty()) return Status::InvalidArgument("no files to import");
  const int b = options.block_size;
  if (b < kMinBlockSize || b > kMaxBlockSize || (b & (b - 1)) != 0)
    return Status::InvalidArgument("block size " + std::to_string(b) +
                                   " is not a power of two from " + std::to_string(kMinBlockSize) +
                                   " to " + std::to_string(kMaxBlockSize));
  impl_->after_block_write = options.after_block_write;
  impl_->progress = options.progress;
  impl_->blocks_done = 0;
  impl_->blocks_expected = 0;
  TB_ASSIGN_OR_RETURN(auto tx, impl_->store.BeginWrite());
  // Read inside the transaction: the token this import replaces is the one last committed.
  TB_RETURN_IF_ERROR(impl_->RefreshToken());
  const uint64_t old_token = impl_->token;
  TB_ASSIGN_OR_RETURN(DemImportReport report, impl_->ImportInTransaction(files, options));
  const uint64_t new_token = NewToken();
  TB_RETURN_IF_ERROR(impl_->store.SetMeta(kCacheTokenKey, std::to_string(new_token)));
  if (options.under_surfaces) {
    // Reads in the hook go through the new token: blocks cached under the old one hold the old
    // cells. On failure the new token's entries hold cells the rollback undid.
    impl_->token = new_token;
  }
  Status written = options.under_surfaces ? options.under_surfaces(report) : Status::Ok();
  if (written.ok()) written = tx->Commit();
  if (!written.ok()) {
    if (options.under_surfaces) {
      impl_->token = old_token;
      DemBlockCache::Instance().EraseStore(new_token);
    }
    return written;
  }
  impl_->token = new_token;
  DemBlockCache::Instance().EraseStore(old_token);
  if (options.progress) options.progress(1.0);  // the overviews' 4/3 is an upper bound
  return report;
}

Result<std::vector<DemInfo>> DemStore::List() {
  TB_RETURN_IF_ERROR(impl_->RefreshToken());
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      impl_->store.db().Cached(std::string(kDemColumns) + "ORDER BY id"));
  std::vector<DemInfo> out;
  for (;;) {
    auto row = stmt->Step();
    if (!row.ok() || !*row) {
      stmt->Reset();
      if (!row.ok()) return row.status();
      break;
    }
    out.push_back(InfoFromRow(*stmt));
  }
  return out;
}

Result<DemInfo> DemStore::Find(const std::string& name) {
  TB_RETURN_IF_ERROR(impl_->RefreshToken());
  TB_ASSIGN_OR_RETURN(auto info,
                      impl_->FindWhere("WHERE name = ?", [&](Statement& st) { st.Bind(1, name); }));
  if (!info) return Status::NotFound("no DEM named " + Quoted(name));
  return std::move(*info);
}

Result<DemInfo> DemStore::FindById(int64_t id) {
  TB_RETURN_IF_ERROR(impl_->RefreshToken());
  TB_ASSIGN_OR_RETURN(auto info,
                      impl_->FindWhere("WHERE id = ?", [&](Statement& st) { st.Bind(1, id); }));
  if (!info) return Status::NotFound("no DEM with id " + std::to_string(id));
  return std::move(*info);
}

Result<std::vector<DemLevelStats>> DemStore::LevelStats(const DemInfo& dem) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      impl_->store.db().Cached("SELECT level, count(*), sum(length(data)) FROM "
                                               "dem_blocks WHERE dem = ? GROUP BY level "
                                               "ORDER BY level"));
  stmt->Bind(1, dem.id);
  std::vector<DemLevelStats> out(static_cast<size_t>(std::max(dem.levels, 1)));
  for (;;) {
    auto row = stmt->Step();
    if (!row.ok() || !*row) {
      stmt->Reset();
      if (!row.ok()) return row.status();
      break;
    }
    const int64_t level = stmt->ColumnInt(0);
    if (level >= 0 && level < static_cast<int64_t>(out.size()))
      out[static_cast<size_t>(level)] = {stmt->ColumnInt(1), stmt->ColumnInt(2)};
  }
  return out;
}

namespace {

// The value of the cell holding (x, y); a point on the east or south edge of the grid takes the
// last column or row. NaN outside the grid.
template <typename CellFn>
double SampleNearest(const GridGeometry& g, double x, double y, CellFn&& cell) {
  if (!g.Contains(x, y)) return std::numeric_limits<double>::quiet_NaN();
  const int64_t col =
      std::min(static_cast<int64_t>(std::floor((x - g.origin_x) / g.cell_x)), g.width - 1);
  const int64_t row =
      std::min(static_cast<int64_t>(std::floor((y - g.origin_y) / g.cell_y)), g.height - 1);
  return cell(std::max<int64_t>(col, 0), std::max<int64_t>(row, 0));
}

template <typename CellFn>
double SampleWith(DemSampling method, const GridGeometry& g, double x, double y, CellFn&& cell) {
  return method == DemSampling::kNearest ? SampleNearest(g, x, y, cell)
                                         : SampleBilinear(g, x, y, cell);
}

}  // namespace

Result<double> DemStore::Sample(const DemInfo& dem, double x, double y, DemSampling method) {
  if (!dem.geometry.Contains(x, y))
    return Status::InvalidArgument("point " + Point(x, y) + " is outside DEM " + Quoted(dem.name));
  Impl::CellReader reader(*impl_, dem, 0);
  const double z = SampleWith(method, dem.geometry, x, y, reader);
  TB_RETURN_IF_ERROR(reader.status());
  if (std::isnan(z))
    return Status::NotFound("no data at " + Point(x, y) + " in DEM " + Quoted(dem.name));
  return z;
}

Result<double> DemStore::Elevation(const DemInfo& dem, double x, double y) {
  if (!dem.geometry.Contains(x, y)) return std::numeric_limits<double>::quiet_NaN();
  Impl::CellReader reader(*impl_, dem, 0);
  const double z = SampleBilinear(dem.geometry, x, y, reader);
  TB_RETURN_IF_ERROR(reader.status());
  return z;
}

Status DemStore::SampleMany(const DemInfo& dem, std::span<const double> xs,
                            std::span<const double> ys, std::span<double> out, DemSampling method) {
  if (xs.size() != ys.size() || xs.size() != out.size())
    return Status::InvalidArgument("SampleMany on DEM " + Quoted(dem.name) + ": " +
                                   std::to_string(xs.size()) + " x, " + std::to_string(ys.size()) +
                                   " y and " + std::to_string(out.size()) +
                                   " outputs differ in number");
  Impl::CellReader reader(*impl_, dem, 0);
  for (size_t i = 0; i < xs.size(); ++i) {
    out[i] = SampleWith(method, dem.geometry, xs[i], ys[i], reader);
    if (!reader.status().ok()) return reader.status();
  }
  return Status::Ok();
}

Result<std::vector<DemStore::Impl::StoredBlock>> DemStore::Impl::ListBlocks(
    const DemInfo& dem, int level, int64_t bx_lo, int64_t bx_hi, int64_t by_lo, int64_t by_hi) {
  // The block extents alone, from the covering index dem_blocks_extent: reading a row's zmin
  // past its blob would walk every overflow page of the blob.
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("SELECT bx, by, zmin, zmax FROM dem_blocks "
                                        "WHERE dem = ? AND level = ? AND bx BETWEEN ? AND ? "
                                        "AND by BETWEEN ? AND ? ORDER BY by, bx"));
  stmt->Bind(1, dem.id).Bind(2, static_cast<int64_t>(level));
  stmt->Bind(3, bx_lo).Bind(4, bx_hi).Bind(5, by_lo).Bind(6, by_hi);
  std::vector<StoredBlock> out;
  for (;;) {
    auto row = stmt->Step();
    if (!row.ok() || !*row) {
      stmt->Reset();  // before returning: callers read blocks, which may use this statement
      TB_RETURN_IF_ERROR(row.status());
      return out;
    }
    out.push_back(StoredBlock{stmt->ColumnInt(0), stmt->ColumnInt(1),
                              static_cast<float>(stmt->ColumnDouble(2)),
                              static_cast<float>(stmt->ColumnDouble(3)), nullptr});
  }
}

Status DemStore::Impl::LoadCells(const DemInfo& dem, int level, std::span<StoredBlock> blocks) {
  if (token == 0) TB_RETURN_IF_ERROR(RefreshToken());
  DemBlockCache& cache = DemBlockCache::Instance();
  struct Miss {
    StoredBlock* block = nullptr;
    int codec = 0;
    std::vector<uint8_t> bytes;
    Status status;
  };
  std::vector<Miss> misses;
  for (StoredBlock& block : blocks) {
    const DemBlockKey key{token, dem.id, level, block.bx, block.by};
    if (cache.Lookup(key, &block.cells) && block.cells) continue;
    TB_ASSIGN_OR_RETURN(Statement * stmt,
                        store.db().Cached("SELECT codec, data FROM dem_blocks "
                                          "WHERE dem = ? AND level = ? AND bx = ? AND by = ?"));
    stmt->Bind(1, dem.id).Bind(2, static_cast<int64_t>(level)).Bind(3, block.bx).Bind(4, block.by);
    auto row = stmt->Step();
    Miss miss;
    miss.block = &block;
    if (row.ok() && *row) {
      size_t size = 0;
      const uint8_t* data = stmt->ColumnBlob(1, &size);
      miss.codec = static_cast<int>(stmt->ColumnInt(0));
      miss.bytes.assign(data, data + size);
    }
    stmt->Reset();
    TB_RETURN_IF_ERROR(row.status());
    if (!*row) return Status::Corruption("DEM " + Quoted(dem.name) + " block vanished");
    misses.push_back(std::move(miss));
  }
  const size_t cells = static_cast<size_t>(dem.block_size) * dem.block_size;
  // Decoding dominates a cold read: the blocks are decoded in parallel, each into its own
  // buffer, so the result does not depend on the thread count.
  tbb::parallel_for(size_t{0}, misses.size(), [&](size_t i) {
    auto out = std::make_shared<std::vector<float>>(cells);
    misses[i].status = DecodeBlockInto(misses[i].codec, misses[i].bytes, *out);
    misses[i].block->cells = std::move(out);
  });
  for (size_t i = 0; i < misses.size(); ++i) {
    StoredBlock& block = *misses[i].block;
    if (!misses[i].status.ok())
      return DamagedBlock(misses[i].status, dem, level, block.bx, block.by);
    cache.Insert(DemBlockKey{token, dem.id, level, block.bx, block.by}, block.cells);
  }
  return Status::Ok();
}

namespace {

BlockRange BlocksOf(const DemLevel& lv, int64_t b, const CellRange& range) {
  return BlockRange{
      FloorDiv(range.col_lo - lv.block_col0, b), FloorDiv(range.col_hi - lv.block_col0, b),
      FloorDiv(range.row_lo - lv.block_row0, b), FloorDiv(range.row_hi - lv.block_row0, b)};
}

// ForEachBlock decodes and hands out this many blocks at a time, so a visit over a whole DEM
// holds a bounded number of blocks.
constexpr size_t kVisitBatch = 16;

}  // namespace

bool DemStore::Impl::CachedWindow(const DemInfo& dem, int level, const BlockRange& br,
                                  std::vector<StoredBlock>* blocks) {
  if (token == 0) return false;
  DemBlockCache& cache = DemBlockCache::Instance();
  for (int64_t by = br.by_lo; by <= br.by_hi; ++by)
    for (int64_t bx = br.bx_lo; bx <= br.bx_hi; ++bx) {
      Block cells;
      if (!cache.Lookup(DemBlockKey{token, dem.id, level, bx, by}, &cells)) return false;
      if (cells) blocks->push_back(StoredBlock{bx, by, 0, 0, std::move(cells)});
    }
  return true;
}

void DemStore::Impl::CacheAbsent(const DemInfo& dem, int level, const BlockRange& br,
                                 const std::vector<StoredBlock>& stored) {
  if (static_cast<int64_t>(stored.size()) == br.Count()) return;
  std::set<std::pair<int64_t, int64_t>> present;
  for (const StoredBlock& block : stored) present.emplace(block.bx, block.by);
  DemBlockCache& cache = DemBlockCache::Instance();
  for (int64_t by = br.by_lo; by <= br.by_hi; ++by)
    for (int64_t bx = br.bx_lo; bx <= br.bx_hi; ++bx)
      if (!present.contains({bx, by}))
        cache.Insert(DemBlockKey{token, dem.id, level, bx, by}, nullptr);
}

Status DemStore::Impl::VisitBlocks(const DemInfo& dem, int level, const CellRange& range,
                                   const std::function<Status(const DemBlock&)>& fn) {
  const DemLevel lv = LevelOf(dem, level);
  const int64_t b = dem.block_size;
  const BlockRange br = BlocksOf(lv, b, range);
  TB_ASSIGN_OR_RETURN(std::vector<StoredBlock> blocks,
                      ListBlocks(dem, level, br.bx_lo, br.bx_hi, br.by_lo, br.by_hi));
  for (size_t first = 0; first < blocks.size(); first += kVisitBatch) {
    const std::span<StoredBlock> batch =
        std::span(blocks).subspan(first, std::min(kVisitBatch, blocks.size() - first));
    TB_RETURN_IF_ERROR(LoadCells(dem, level, batch));
    for (StoredBlock& stored : batch) {
      DemBlock block;
      block.level = level;
      block.bx = stored.bx;
      block.by = stored.by;
      block.zmin = stored.zmin;
      block.zmax = stored.zmax;
      block.geometry = lv.geometry;
      block.geometry.origin_x +=
          static_cast<double>(lv.block_col0 + block.bx * b) * lv.geometry.cell_x;
      block.geometry.origin_y +=
          static_cast<double>(lv.block_row0 + block.by * b) * lv.geometry.cell_y;
      block.geometry.width = b;
      block.geometry.height = b;
      block.cells = stored.cells.get();
      TB_RETURN_IF_ERROR(fn(block));
      stored.cells.reset();
    }
  }
  return Status::Ok();
}

Status DemStore::Impl::ReadCells(const DemInfo& dem, int level, const CellRange& range,
                                 Grid* grid) {
  const DemLevel lv = LevelOf(dem, level);
  grid->geometry = lv.geometry;
  grid->geometry.origin_x += static_cast<double>(range.col_lo) * lv.geometry.cell_x;
  grid->geometry.origin_y += static_cast<double>(range.row_lo) * lv.geometry.cell_y;
  grid->geometry.width = range.col_hi - range.col_lo + 1;
  grid->geometry.height = range.row_hi - range.row_lo + 1;
  grid->crs_wkt = dem.crs_wkt;
  grid->source_nodata = dem.nodata;
  const int64_t b = dem.block_size;
  const BlockRange br = BlocksOf(lv, b, range);
  std::vector<StoredBlock> blocks;
  if (!CachedWindow(dem, level, br, &blocks)) {
    TB_ASSIGN_OR_RETURN(blocks, ListBlocks(dem, level, br.bx_lo, br.bx_hi, br.by_lo, br.by_hi));
    CacheAbsent(dem, level, br, blocks);
  }
  grid->cells.resize(static_cast<size_t>(grid->geometry.CellCount()));
  // Only cells no stored block covers are nodata: when every block is there, none.
  if (static_cast<int64_t>(blocks.size()) < br.Count())
    std::fill(grid->cells.begin(), grid->cells.end(), kNaN);
  for (size_t first = 0; first < blocks.size(); first += kVisitBatch) {
    const std::span<StoredBlock> batch =
        std::span(blocks).subspan(first, std::min(kVisitBatch, blocks.size() - first));
    TB_RETURN_IF_ERROR(LoadCells(dem, level, batch));
    for (StoredBlock& block : batch) {
      const int64_t col0 = lv.block_col0 + block.bx * b;  // the block's first cell in the level
      const int64_t row0 = lv.block_row0 + block.by * b;
      // Row by row, the part of each block row inside the window in one copy.
      const int64_t c_lo = std::max(col0, range.col_lo);
      const int64_t c_hi = std::min(col0 + b - 1, range.col_hi);
      for (int64_t r = std::max(row0, range.row_lo); r <= std::min(row0 + b - 1, range.row_hi); ++r)
        std::copy_n(
            block.cells->data() + (r - row0) * b + (c_lo - col0), c_hi - c_lo + 1,
            grid->cells.data() + (r - range.row_lo) * grid->geometry.width + (c_lo - range.col_lo));
      block.cells.reset();
    }
  }
  return Status::Ok();
}

namespace {
Status CheckLevel(const DemInfo& dem, int level) {
  if (level < 0 || level >= dem.levels)
    return Status::InvalidArgument("DEM " + Quoted(dem.name) + " has no level " +
                                   std::to_string(level) + " (levels 0 to " +
                                   std::to_string(dem.levels - 1) + ")");
  return Status::Ok();
}
}  // namespace

Result<std::shared_ptr<const std::vector<float>>> DemStore::ReadBlock(const DemInfo& dem, int level,
                                                                      int64_t bx, int64_t by) {
  TB_RETURN_IF_ERROR(CheckLevel(dem, level));
  return impl_->CachedBlock(dem, level, bx, by);
}

Result<Grid> DemStore::ReadGrid(const DemInfo& dem) {
  Grid grid;
  TB_RETURN_IF_ERROR(impl_->ReadCells(
      dem, 0, CellRange{0, dem.geometry.width - 1, 0, dem.geometry.height - 1}, &grid));
  return grid;
}

Result<Grid> DemStore::ReadWindow(const DemInfo& dem, const DemBox& box, int level) {
  Grid grid;
  TB_RETURN_IF_ERROR(ReadWindow(dem, box, level, &grid));
  return grid;
}

Status DemStore::ReadWindow(const DemInfo& dem, const DemBox& box, int level, Grid* out) {
  TB_RETURN_IF_ERROR(CheckLevel(dem, level));
  TB_ASSIGN_OR_RETURN(CellRange range, CellsIn(LevelOf(dem, level).geometry, box, dem.name));
  return impl_->ReadCells(dem, level, range, out);
}

Status DemStore::ForEachBlock(const DemInfo& dem, const DemBox& box, int level,
                              const std::function<Status(const DemBlock&)>& fn) {
  TB_RETURN_IF_ERROR(CheckLevel(dem, level));
  TB_ASSIGN_OR_RETURN(CellRange range, CellsIn(LevelOf(dem, level).geometry, box, dem.name));
  return impl_->VisitBlocks(dem, level, range, fn);
}

Result<std::pair<double, double>> DemStore::Relief(const DemInfo& dem) {
  TB_ASSIGN_OR_RETURN(
      Statement * q,
      impl_->store.db().Cached(
          "SELECT min(zmin), max(zmax) FROM dem_blocks WHERE dem = ? AND level = 0"));
  q->Bind(1, dem.id);
  TB_ASSIGN_OR_RETURN(bool row, q->Step());
  std::pair<double, double> relief{0, 0};
  if (row && !q->ColumnIsNull(0)) relief = {q->ColumnDouble(0), q->ColumnDouble(1)};
  q->Reset();
  return relief;
}

Result<int> DemStore::ClipLevel(const DemInfo& dem, const DemBox& box, int64_t max_cells) {
  for (int level = 0;; ++level) {
    TB_ASSIGN_OR_RETURN(CellRange range, CellsIn(LevelOf(dem, level).geometry, box, dem.name));
    const int64_t cells = (range.col_hi - range.col_lo + 1) * (range.row_hi - range.row_lo + 1);
    if (cells <= max_cells || level + 1 >= dem.levels) return level;
  }
}

Result<DemClip> DemStore::Clip(const DemInfo& dem, const DemBox& box, int64_t max_cells,
                               const std::string& path) {
  TB_ASSIGN_OR_RETURN(const int level, ClipLevel(dem, box, max_cells));
  TB_ASSIGN_OR_RETURN(const CellRange range, CellsIn(LevelOf(dem, level).geometry, box, dem.name));
  Grid grid;
  TB_RETURN_IF_ERROR(impl_->ReadCells(dem, level, range, &grid));
  TB_RETURN_IF_ERROR(WriteGeoTiff(grid, path));
  return DemClip{level, grid.geometry};
}

}  // namespace tinbase
