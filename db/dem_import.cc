// DemStore::Import: sheets (GDAL rasters) placed on one grid, warped onto the store's CRS when
// they are in another, and written block by block into a new or extended DEM (a mosaic), with the
// overviews above the blocks written, in one transaction.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

#include "core/base/object_name.h"
#include "core/raster/block_codec.h"
#include "core/raster/gdal_raster.h"
#include "db/dem_import_checks.h"
#include "db/dem_store.h"
#include "db/dem_store_impl.h"

namespace tinbase {

using dem_internal::FloorDiv;
using dem_internal::kCacheTokenKey;
using dem_internal::kNaN;
using dem_internal::LevelCount;
using dem_internal::NewToken;
using dem_internal::Point;
using dem_internal::Quoted;
using dem_internal::Sheet;

namespace {

constexpr int kMinBlockSize = 8;
constexpr int kMaxBlockSize = 4096;

// A whole number of cells `offset / cell` away, or nullopt when the grids do not line up. The
// tolerance (1e-6 of a cell) absorbs the round-off of origins written as decimal text.
std::optional<int64_t> WholeCells(double offset, double cell) {
  const double cells = offset / cell;
  const double rounded = std::round(cells);
  if (std::abs(cells - rounded) > 1e-6) return std::nullopt;
  return static_cast<int64_t>(rounded);
}

bool SameCellSize(double a, double b) { return std::abs(a - b) <= 1e-9 * std::abs(b); }

}  // namespace

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

namespace {

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

}  // namespace

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

}  // namespace tinbase
