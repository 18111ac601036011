// DemStore's reads: sampling points (bilinear or nearest), windows of a level, visits of its
// blocks, and clips written to GeoTIFF. Cells come through the block caches (db/dem_blocks.cc).
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <span>

#include "core/raster/bilinear.h"
#include "core/raster/gdal_raster.h"
#include "core/raster/grid.h"
#include "db/dem_store.h"
#include "db/dem_store_impl.h"

namespace tinbase {

using dem_internal::BlockRange;
using dem_internal::CellRange;
using dem_internal::FloorDiv;
using dem_internal::kNaN;
using dem_internal::Point;
using dem_internal::Quoted;

namespace {

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

}  // namespace

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
