// DemStore's lookups (List, Find, FindById, LevelStats), the level grids (LevelOf) and the
// store's DEM cache token. The rest of DemStore: see db/dem_store_impl.h.
#include "db/dem_store.h"

#include <cstdio>
#include <cstdlib>
#include <random>

#include "db/dem_store_impl.h"
#include "db/sql/each_row.h"

namespace tinbase {

using dem_internal::FloorDiv;
using dem_internal::kCacheTokenKey;
using dem_internal::NewToken;
using dem_internal::Quoted;

namespace {

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

namespace dem_internal {

std::string Point(double x, double y) {
  char buf[80];
  std::snprintf(buf, sizeof buf, "(%.10g, %.10g)", x, y);
  return buf;
}

// A fresh random cache token, never 0 (0 means "not read yet"). Drawn from the OS each time:
// a generator seeded once would hand a forked child the parent's next tokens, and two stores
// with one token share cache entries.
uint64_t NewToken() {
  std::random_device os;
  uint64_t t = 0;
  while (t == 0) t = os() ^ (static_cast<uint64_t>(os()) << 32);
  return t;
}

}  // namespace dem_internal

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

Status DemStore::Impl::RefreshToken() {
  TB_ASSIGN_OR_RETURN(std::optional<std::string> value, store.GetMeta(kCacheTokenKey));
  uint64_t t = 0;
  if (value) t = std::strtoull(value->c_str(), nullptr, 10);
  // A store no import of this version has touched: a token of this DemStore alone, never shared.
  if (t == 0) t = token != 0 ? token : NewToken();
  token = t;
  return Status::Ok();
}

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

DemStore::DemStore(Store& store) : impl_(std::make_unique<Impl>(store)) {}
DemStore::~DemStore() = default;

Result<std::vector<DemInfo>> DemStore::List() {
  TB_RETURN_IF_ERROR(impl_->RefreshToken());
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      impl_->store.db().Cached(std::string(kDemColumns) + "ORDER BY id"));
  std::vector<DemInfo> out;
  TB_RETURN_IF_ERROR(EachRow(*stmt, [&](Statement& row) { out.push_back(InfoFromRow(row)); }));
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
  TB_RETURN_IF_ERROR(EachRow(*stmt, [&](Statement& row) {
    const int64_t level = row.ColumnInt(0);
    if (level >= 0 && level < static_cast<int64_t>(out.size()))
      out[static_cast<size_t>(level)] = {row.ColumnInt(1), row.ColumnInt(2)};
  }));
  return out;
}

}  // namespace tinbase
