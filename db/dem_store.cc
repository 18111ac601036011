#include "db/dem_store.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <list>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <span>
#include <tuple>

#include "core/raster/bilinear.h"
#include "core/raster/block_codec.h"
#include "core/raster/gdal_raster.h"

namespace tinbase {

namespace {

constexpr int kMinBlockSize = 8;
constexpr int kMaxBlockSize = 4096;
// Decoded blocks kept for Sample: 64 blocks of 256 x 256 float32 are 16 MiB.
constexpr size_t kBlockCacheCapacity = 64;
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

constexpr const char* kDemColumns =
    "SELECT id, name, crs_wkt, origin_x, origin_y, cell_x, cell_y, width, height, block_size, "
    "nodata, levels, sources FROM dems ";

Result<DemInfo> InfoFromRow(const Statement& row) {
  DemInfo info;
  info.id = row.ColumnInt(0);
  info.name = row.ColumnText(1);
  info.crs_wkt = row.ColumnText(2);
  info.geometry = GridGeometry{row.ColumnDouble(3), row.ColumnDouble(4), row.ColumnDouble(5),
                               row.ColumnDouble(6), row.ColumnInt(7),    row.ColumnInt(8)};
  info.block_size = static_cast<int>(row.ColumnInt(9));
  if (!row.ColumnIsNull(10)) info.nodata = row.ColumnDouble(10);
  info.levels = static_cast<int>(row.ColumnInt(11));
  const auto sources = nlohmann::json::parse(row.ColumnText(12), nullptr, false);
  if (sources.is_discarded() || !sources.is_array())
    return Status::Corruption("DEM " + Quoted(info.name) + ": sources is not a JSON list");
  if (!sources.empty()) {
    const auto& first = sources.front();
    if (!first.contains("origin_x") || !first.contains("origin_y"))
      return Status::Corruption("DEM " + Quoted(info.name) + ": first source has no origin");
    info.block_col0 = std::llround((first["origin_x"].get<double>() - info.geometry.origin_x) /
                                   info.geometry.cell_x);
    info.block_row0 = std::llround((first["origin_y"].get<double>() - info.geometry.origin_y) /
                                   info.geometry.cell_y);
  }
  return info;
}

}  // namespace

struct DemStore::Impl {
  explicit Impl(Store& s) : store(s) {}

  // A decoded block, or null when none is stored there (all nodata).
  using Block = std::shared_ptr<const std::vector<float>>;
  using Key = std::tuple<int64_t, int, int64_t, int64_t>;  // dem, level, bx, by

  Result<std::optional<DemInfo>> FindWhere(const std::string& where, const std::string& text,
                                           int64_t id);
  Result<Block> LoadBlock(const DemInfo& dem, int level, int64_t bx, int64_t by);
  Result<Block> CachedBlock(const DemInfo& dem, int level, int64_t bx, int64_t by);
  void ClearCache() {
    lru.clear();
    index.clear();
  }

  Result<DemImportReport> ImportInTransaction(const std::vector<std::string>& files,
                                              const DemImportOptions& options);
  Result<Crs> StoreCrsFor(const GdalRaster& first);
  Status WriteBlock(const DemInfo& dem, int64_t bx, int64_t by, const std::vector<float>& cells,
                    DemImportReport* report);

  Store& store;
  std::list<std::pair<Key, Block>> lru;  // most recently used first
  std::map<Key, std::list<std::pair<Key, Block>>::iterator> index;
};

Result<std::optional<DemInfo>> DemStore::Impl::FindWhere(const std::string& where,
                                                         const std::string& text, int64_t id) {
  TB_ASSIGN_OR_RETURN(Statement * stmt, store.db().Cached(kDemColumns + where));
  if (where.find("name") != std::string::npos) {
    stmt->Bind(1, text);
  } else {
    stmt->Bind(1, id);
  }
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  std::optional<DemInfo> info;
  if (row) {
    auto parsed = InfoFromRow(*stmt);
    if (!parsed.ok()) {
      stmt->Reset();
      return parsed.status();
    }
    info = std::move(parsed).value();
  }
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
  if (!cells.ok())
    return cells.status().WithContext("DEM " + Quoted(dem.name) + ", level " +
                                      std::to_string(level) + " block (" + std::to_string(bx) +
                                      ", " + std::to_string(by) + ")");
  return Block(std::make_shared<const std::vector<float>>(std::move(cells).value()));
}

Result<DemStore::Impl::Block> DemStore::Impl::CachedBlock(const DemInfo& dem, int level, int64_t bx,
                                                          int64_t by) {
  const Key key{dem.id, level, bx, by};
  if (auto it = index.find(key); it != index.end()) {
    lru.splice(lru.begin(), lru, it->second);
    return it->second->second;
  }
  TB_ASSIGN_OR_RETURN(Block block, LoadBlock(dem, level, bx, by));
  lru.emplace_front(key, block);
  index[key] = lru.begin();
  if (lru.size() > kBlockCacheCapacity) {
    index.erase(lru.back().first);
    lru.pop_back();
  }
  return block;
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

Status DemStore::Impl::WriteBlock(const DemInfo& dem, int64_t bx, int64_t by,
                                  const std::vector<float>& cells, DemImportReport* report) {
  float zmin = std::numeric_limits<float>::infinity();
  float zmax = -zmin;
  for (float v : cells) {
    if (std::isnan(v)) continue;
    zmin = std::min(zmin, v);
    zmax = std::max(zmax, v);
  }
  if (zmin > zmax) return Status::Ok();  // all nodata: a missing block reads as NaN
  const std::vector<uint8_t> bytes = EncodeBlock(cells);
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("INSERT OR REPLACE INTO dem_blocks"
                                        "(dem, level, bx, by, codec, data, zmin, zmax) "
                                        "VALUES (?, 0, ?, ?, ?, ?, ?, ?)"));
  stmt->Bind(1, dem.id).Bind(2, bx).Bind(3, by);
  stmt->Bind(4, static_cast<int64_t>(BlockCodec::kBloscZstd));
  stmt->BindBlob(5, bytes.data(), bytes.size());
  stmt->Bind(6, static_cast<double>(zmin)).Bind(7, static_cast<double>(zmax));
  TB_RETURN_IF_ERROR(stmt->Run());
  ++report->blocks_written;
  report->bytes_stored += static_cast<int64_t>(bytes.size());
  return Status::Ok();
}

Result<DemImportReport> DemStore::Impl::ImportInTransaction(const std::vector<std::string>& files,
                                                            const DemImportOptions& options) {
  // Every file is checked before anything is written, so the common failures cost nothing.
  std::vector<GdalRaster> rasters;
  for (const std::string& file : files) {
    TB_ASSIGN_OR_RETURN(GdalRaster raster, GdalRaster::Open(file));
    rasters.push_back(std::move(raster));
  }
  const std::string name =
      options.name.empty() ? std::filesystem::path(files.front()).stem().string() : options.name;
  if (name.empty()) return Status::InvalidArgument(files.front() + ": no name for the DEM");

  DemImportReport report;
  TB_ASSIGN_OR_RETURN(std::optional<DemInfo> existing, FindWhere("WHERE name = ?", name, 0));
  TB_ASSIGN_OR_RETURN(Crs crs, StoreCrsFor(rasters.front()));

  // Place every sheet on the DEM's grid: the existing DEM's, else the first sheet's.
  std::vector<Sheet> sheets;
  std::vector<std::string> source_crs;  // as the files declare it, before any warp
  const std::optional<double> first_nodata = rasters.front().nodata();
  std::optional<GridGeometry> grid;
  if (existing) grid = existing->geometry;
  for (GdalRaster& raster : rasters) {
    source_crs.push_back(raster.crs().Label());
    if (!raster.crs().IsSame(crs)) {
      TB_ASSIGN_OR_RETURN(raster, raster.WarpTo(crs, grid ? &*grid : nullptr));
      report.warped = true;
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
    sheets.push_back(Sheet{raster, *col0, *row0});
    report.cells += g.CellCount();
  }

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
  dem.geometry = *grid;
  dem.geometry.origin_x = grid->origin_x + static_cast<double>(min_col) * grid->cell_x;
  dem.geometry.origin_y = grid->origin_y + static_cast<double>(min_row) * grid->cell_y;
  dem.geometry.width = max_col - min_col;
  dem.geometry.height = max_row - min_row;
  if (existing) {
    dem.block_col0 = existing->block_col0 - min_col;
    dem.block_row0 = existing->block_row0 - min_row;
  } else {
    dem.block_size = options.block_size;
    dem.nodata = first_nodata;
    dem.block_col0 = sheets.front().col0;
    dem.block_row0 = sheets.front().row0;
  }

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

  Statement* upsert = nullptr;
  if (existing) {
    TB_ASSIGN_OR_RETURN(upsert,
                        store.db().Cached("UPDATE dems SET origin_x = ?, origin_y = ?, width = ?, "
                                          "height = ?, sources = ? WHERE id = ?"));
    upsert->Bind(6, existing->id);
  } else {
    TB_ASSIGN_OR_RETURN(
        upsert, store.db().Cached("INSERT INTO dems(origin_x, origin_y, width, height, sources, "
                                  "name, crs_wkt, cell_x, cell_y, block_size, nodata, levels) "
                                  "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, 1)"));
    upsert->Bind(6, dem.name).Bind(7, dem.crs_wkt).Bind(8, dem.geometry.cell_x);
    upsert->Bind(9, dem.geometry.cell_y).Bind(10, static_cast<int64_t>(dem.block_size));
    if (dem.nodata) {
      upsert->Bind(11, *dem.nodata);
    } else {
      upsert->BindNull(11);
    }
  }
  upsert->Bind(1, dem.geometry.origin_x).Bind(2, dem.geometry.origin_y);
  upsert->Bind(3, dem.geometry.width).Bind(4, dem.geometry.height).Bind(5, sources.dump());
  TB_RETURN_IF_ERROR(upsert->Run());
  if (!existing) dem.id = store.db().LastInsertRowId();

  // Blocks touched by any sheet, each assembled once from the stored block and the sheets over it.
  const int64_t b = dem.block_size;
  std::set<std::pair<int64_t, int64_t>> touched;  // (by, bx): row-major, as GDAL reads best
  for (const Sheet& s : sheets) {
    const GridGeometry& g = s.raster.geometry();
    for (int64_t by = FloorDiv(s.row0 - dem.block_row0, b);
         by <= FloorDiv(s.row0 + g.height - 1 - dem.block_row0, b); ++by)
      for (int64_t bx = FloorDiv(s.col0 - dem.block_col0, b);
           bx <= FloorDiv(s.col0 + g.width - 1 - dem.block_col0, b); ++bx)
        touched.emplace(by, bx);
  }
  for (const auto& [by, bx] : touched) {
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
        if (std::isnan(window[i]) || (options.keep_first && !std::isnan(cells[i]))) continue;
        cells[i] = window[i];
      }
    }
    TB_RETURN_IF_ERROR(WriteBlock(dem, bx, by, cells, &report));
  }
  report.dem = dem;
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
  impl_->ClearCache();
  TB_ASSIGN_OR_RETURN(auto tx, impl_->store.BeginWrite());
  TB_ASSIGN_OR_RETURN(DemImportReport report, impl_->ImportInTransaction(files, options));
  TB_RETURN_IF_ERROR(tx->Commit());
  return report;
}

Result<std::vector<DemInfo>> DemStore::List() {
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
    auto info = InfoFromRow(*stmt);
    if (!info.ok()) {
      stmt->Reset();
      return info.status();
    }
    out.push_back(std::move(info).value());
  }
  return out;
}

Result<DemInfo> DemStore::Find(const std::string& name) {
  TB_ASSIGN_OR_RETURN(auto info, impl_->FindWhere("WHERE name = ?", name, 0));
  if (!info) return Status::NotFound("no DEM named " + Quoted(name));
  return std::move(*info);
}

Result<DemInfo> DemStore::FindById(int64_t id) {
  TB_ASSIGN_OR_RETURN(auto info, impl_->FindWhere("WHERE id = ?", "", id));
  if (!info) return Status::NotFound("no DEM with id " + std::to_string(id));
  return std::move(*info);
}

Result<double> DemStore::Sample(const DemInfo& dem, double x, double y) {
  if (!dem.geometry.Contains(x, y))
    return Status::InvalidArgument("point " + Point(x, y) + " is outside DEM " + Quoted(dem.name));
  const int64_t b = dem.block_size;
  Status failure;
  const double z = SampleBilinear(dem.geometry, x, y, [&](int64_t col, int64_t row) -> float {
    const int64_t bx = FloorDiv(col - dem.block_col0, b);
    const int64_t by = FloorDiv(row - dem.block_row0, b);
    auto block = impl_->CachedBlock(dem, 0, bx, by);
    if (!block.ok()) {
      if (failure.ok()) failure = block.status();
      return kNaN;
    }
    if (!*block) return kNaN;
    const int64_t c = col - dem.block_col0 - bx * b;
    const int64_t r = row - dem.block_row0 - by * b;
    return (**block)[static_cast<size_t>(r * b + c)];
  });
  TB_RETURN_IF_ERROR(failure);
  if (std::isnan(z))
    return Status::NotFound("no data at " + Point(x, y) + " in DEM " + Quoted(dem.name));
  return z;
}

Result<Grid> DemStore::ReadGrid(const DemInfo& dem) {
  Grid grid;
  grid.geometry = dem.geometry;
  grid.crs_wkt = dem.crs_wkt;
  grid.source_nodata = dem.nodata;
  grid.cells.assign(static_cast<size_t>(dem.geometry.CellCount()), kNaN);
  TB_ASSIGN_OR_RETURN(Statement * stmt, impl_->store.db().Cached("SELECT bx, by FROM dem_blocks "
                                                                 "WHERE dem = ? AND level = 0"));
  stmt->Bind(1, dem.id);
  std::vector<std::pair<int64_t, int64_t>> blocks;
  for (;;) {
    auto row = stmt->Step();
    if (!row.ok()) {
      stmt->Reset();
      return row.status();
    }
    if (!*row) break;
    blocks.emplace_back(stmt->ColumnInt(0), stmt->ColumnInt(1));
  }
  stmt->Reset();
  const int64_t b = dem.block_size;
  for (const auto& [bx, by] : blocks) {
    TB_ASSIGN_OR_RETURN(Impl::Block block, impl_->LoadBlock(dem, 0, bx, by));
    const int64_t col0 = dem.block_col0 + bx * b;
    const int64_t row0 = dem.block_row0 + by * b;
    for (int64_t r = std::max<int64_t>(row0, 0); r < std::min(row0 + b, dem.geometry.height); ++r)
      for (int64_t c = std::max<int64_t>(col0, 0); c < std::min(col0 + b, dem.geometry.width); ++c)
        grid.cells[static_cast<size_t>(r * dem.geometry.width + c)] =
            (*block)[static_cast<size_t>((r - row0) * b + (c - col0))];
  }
  return grid;
}

}  // namespace tinbase
