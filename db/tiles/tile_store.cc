// TileStore: see tile_store.h.
#include "db/tiles/tile_store.h"

namespace tinbase {

Result<std::optional<TilePyramidInfo>> TileStore::Pyramid(int64_t surface) {
  TB_ASSIGN_OR_RETURN(
      Statement * s, db_.Cached("SELECT max_zoom, extensions, water_tag, min_height, max_height, "
                                "tx, min_vertex, max_vertex FROM tile_pyramids WHERE surface = ?"));
  s->Bind(1, surface);
  TB_ASSIGN_OR_RETURN(const bool found, s->Step());
  if (!found) return std::optional<TilePyramidInfo>();
  TilePyramidInfo info;
  info.surface = surface;
  info.max_zoom = static_cast<int>(s->ColumnInt(0));
  info.extensions = s->ColumnText(1);
  if (!s->ColumnIsNull(2)) info.water_tag = s->ColumnText(2);
  info.min_height = s->ColumnDouble(3);
  info.max_height = s->ColumnDouble(4);
  info.tx = s->ColumnInt(5);
  if (!s->ColumnIsNull(6)) info.min_vertex = s->ColumnInt(6);
  if (!s->ColumnIsNull(7)) info.max_vertex = s->ColumnInt(7);
  s->Reset();
  return std::optional<TilePyramidInfo>(info);
}

Status TileStore::DeletePyramid(int64_t surface) {
  for (const char* sql :
       {"DELETE FROM tiles WHERE surface = ?", "DELETE FROM tile_levels WHERE surface = ?",
        "DELETE FROM tile_pyramids WHERE surface = ?"}) {
    TB_ASSIGN_OR_RETURN(Statement * s, db_.Cached(sql));
    s->Bind(1, surface);
    TB_RETURN_IF_ERROR(s->Run());
  }
  return Status::Ok();
}

Status TileStore::ReplacePyramid(const TilePyramidInfo& info) {
  TB_RETURN_IF_ERROR(DeletePyramid(info.surface));
  TB_ASSIGN_OR_RETURN(Statement * s,
                      db_.Cached("INSERT INTO tile_pyramids(surface, max_zoom, extensions, "
                                 "water_tag, min_height, max_height, tx, min_vertex, max_vertex) "
                                 "VALUES (?,?,?,?,?,?,?,?,?)"));
  s->Bind(1, info.surface).Bind(2, int64_t{info.max_zoom}).Bind(3, info.extensions);
  if (info.water_tag) {
    s->Bind(4, *info.water_tag);
  } else {
    s->BindNull(4);
  }
  s->Bind(5, info.min_height).Bind(6, info.max_height).Bind(7, info.tx);
  int column = 8;
  for (const std::optional<int64_t>& vertex : {info.min_vertex, info.max_vertex}) {
    if (vertex) {
      s->Bind(column, *vertex);
    } else {
      s->BindNull(column);
    }
    ++column;
  }
  return s->Run();
}

Status TileStore::PutLevel(int64_t surface, int level, double geometric_error) {
  TB_ASSIGN_OR_RETURN(Statement * s, db_.Cached("INSERT INTO tile_levels(surface, level, "
                                                "geometric_error) VALUES (?,?,?) "
                                                "ON CONFLICT (surface, level) DO UPDATE SET "
                                                "geometric_error = excluded.geometric_error"));
  s->Bind(1, surface).Bind(2, int64_t{level}).Bind(3, geometric_error);
  return s->Run();
}

Status TileStore::PutTile(int64_t surface, const TileKey& key, const std::vector<uint8_t>& data,
                          int64_t tx) {
  TB_ASSIGN_OR_RETURN(
      Statement * s,
      db_.Cached("INSERT INTO tiles(surface, level, x, y, data, tx) VALUES (?,?,?,?,?,?) "
                 "ON CONFLICT (surface, level, x, y) DO UPDATE SET "
                 "data = excluded.data, tx = excluded.tx"));
  s->Bind(1, surface).Bind(2, int64_t{key.level}).Bind(3, key.x).Bind(4, key.y);
  s->BindBlob(5, data.data(), data.size()).Bind(6, tx);
  return s->Run();
}

Status TileStore::DeleteTile(int64_t surface, const TileKey& key) {
  TB_ASSIGN_OR_RETURN(Statement * s, db_.Cached("DELETE FROM tiles WHERE surface = ? AND level = ? "
                                                "AND x = ? AND y = ?"));
  s->Bind(1, surface).Bind(2, int64_t{key.level}).Bind(3, key.x).Bind(4, key.y);
  return s->Run();
}

Status TileStore::SetPyramidTx(int64_t surface, int64_t tx) {
  TB_ASSIGN_OR_RETURN(Statement * s,
                      db_.Cached("UPDATE tile_pyramids SET tx = ? WHERE surface = ?"));
  s->Bind(1, tx).Bind(2, surface);
  return s->Run();
}

Status TileStore::SetHeightVertices(int64_t surface, int64_t min_vertex, int64_t max_vertex) {
  TB_ASSIGN_OR_RETURN(Statement * s, db_.Cached("UPDATE tile_pyramids SET min_vertex = ?, "
                                                "max_vertex = ? WHERE surface = ?"));
  s->Bind(1, min_vertex).Bind(2, max_vertex).Bind(3, surface);
  return s->Run();
}

Result<std::optional<std::pair<std::vector<uint8_t>, int64_t>>> TileStore::Tile(
    int64_t surface, const TileKey& key) {
  using Answer = std::optional<std::pair<std::vector<uint8_t>, int64_t>>;
  TB_ASSIGN_OR_RETURN(Statement * s, db_.Cached("SELECT data, tx FROM tiles WHERE surface = ? "
                                                "AND level = ? AND x = ? AND y = ?"));
  s->Bind(1, surface).Bind(2, int64_t{key.level}).Bind(3, key.x).Bind(4, key.y);
  TB_ASSIGN_OR_RETURN(const bool found, s->Step());
  if (!found) return Answer();
  size_t size = 0;
  const uint8_t* data = s->ColumnBlob(0, &size);
  Answer out(std::in_place, std::vector<uint8_t>(data, data + size), s->ColumnInt(1));
  s->Reset();
  return out;
}

Result<std::set<TileKey>> TileStore::Keys(int64_t surface) {
  TB_ASSIGN_OR_RETURN(Statement * s, db_.Cached("SELECT level, x, y FROM tiles WHERE surface = ?"));
  s->Bind(1, surface);
  std::set<TileKey> keys;
  while (true) {
    TB_ASSIGN_OR_RETURN(const bool row, s->Step());
    if (!row) break;
    keys.insert({static_cast<int>(s->ColumnInt(0)), s->ColumnInt(1), s->ColumnInt(2)});
  }
  return keys;
}

Result<std::vector<std::pair<int, double>>> TileStore::Levels(int64_t surface) {
  TB_ASSIGN_OR_RETURN(Statement * s, db_.Cached("SELECT level, geometric_error FROM tile_levels "
                                                "WHERE surface = ? ORDER BY level"));
  s->Bind(1, surface);
  std::vector<std::pair<int, double>> levels;
  while (true) {
    TB_ASSIGN_OR_RETURN(const bool row, s->Step());
    if (!row) break;
    levels.emplace_back(static_cast<int>(s->ColumnInt(0)), s->ColumnDouble(1));
  }
  return levels;
}

Result<std::pair<int64_t, int64_t>> TileStore::CountAndBytes(int64_t surface) {
  TB_ASSIGN_OR_RETURN(Statement * s, db_.Cached("SELECT count(*), coalesce(sum(length(data)), 0) "
                                                "FROM tiles WHERE surface = ?"));
  s->Bind(1, surface);
  TB_ASSIGN_OR_RETURN(const bool row, s->Step());
  std::pair<int64_t, int64_t> out{0, 0};
  if (row) out = {s->ColumnInt(0), s->ColumnInt(1)};
  s->Reset();
  return out;
}

Result<int64_t> LatestChange(Connection& db) {
  TB_ASSIGN_OR_RETURN(Statement * s, db.Cached("SELECT coalesce(max(tx), 0) FROM changes"));
  TB_ASSIGN_OR_RETURN(const bool row, s->Step());
  const int64_t tx = row ? s->ColumnInt(0) : 0;
  s->Reset();
  return tx;
}

}  // namespace tinbase
