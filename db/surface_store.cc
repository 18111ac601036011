#include "db/surface_store.h"

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "db/sqlite/scoped_page_cache.h"

namespace tinbase {

namespace {

constexpr char kSurfaceColumns[] =
    "SELECT id, name, kind, method, tolerance, dem, block_origin_x, block_origin_y, block_size "
    "FROM surfaces ";

constexpr char kTriangleColumns[] =
    "SELECT t.id, t.v0, t.v1, t.v2, t.n0, t.n1, t.n2, t.visible, g.value, t.block "
    "FROM triangles t LEFT JOIN tags g ON g.id = t.tag ";

std::string Quoted(const std::string& name) { return "'" + name + "'"; }

SurfaceInfo SurfaceFromRow(const Statement& row) {
  SurfaceInfo info;
  info.id = row.ColumnInt(0);
  info.name = row.ColumnText(1);
  if (!ParseSurfaceKind(row.ColumnText(2), &info.kind)) info.kind = SurfaceKind::kFree;
  info.method = row.ColumnText(3);
  if (!row.ColumnIsNull(4)) info.tolerance = row.ColumnDouble(4);
  if (!row.ColumnIsNull(5)) info.dem = row.ColumnInt(5);
  info.blocks = BlockGrid{row.ColumnDouble(6), row.ColumnDouble(7), row.ColumnDouble(8)};
  return info;
}

// Reads the columns of kTriangleColumns.
StoredTriangle TriangleFromRow(const Statement& row) {
  StoredTriangle t;
  t.id = row.ColumnInt(0);
  for (int i = 0; i < 3; ++i) {
    t.v[i] = row.ColumnInt(1 + i);
    if (!row.ColumnIsNull(4 + i)) t.n[i] = row.ColumnInt(4 + i);
  }
  t.visible = row.ColumnInt(7) != 0;
  if (!row.ColumnIsNull(8)) t.tag = row.ColumnText(8);
  t.block = row.ColumnInt(9);
  return t;
}

// InvalidArgument naming the first index of `tin` that points outside it.
Status ValidateIndices(const Tin& tin) {
  const size_t nv = tin.vertices.size();
  const size_t nt = tin.triangles.size();
  for (size_t i = 0; i < nv; ++i) {
    const TinVertex& v = tin.vertices[i];
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      return Status::InvalidArgument("vertex " + std::to_string(i) + ": coordinates not finite");
  }
  for (size_t t = 0; t < nt; ++t) {
    const TinTriangle& tri = tin.triangles[t];
    const auto where = [t] { return "triangle " + std::to_string(t) + ": "; };
    for (int i = 0; i < 3; ++i) {
      if (tri.v[i] >= nv)
        return Status::InvalidArgument(where() + "vertex " + std::to_string(tri.v[i]) +
                                       " does not exist (" + std::to_string(nv) + " vertices)");
      if (tri.n[i] != kNoNeighbour && (tri.n[i] < 0 || static_cast<size_t>(tri.n[i]) >= nt))
        return Status::InvalidArgument(where() + "neighbour " + std::to_string(tri.n[i]) +
                                       " does not exist");
    }
    if (tri.tag != kNoTag && (tri.tag < 0 || static_cast<size_t>(tri.tag) >= tin.tags.size()))
      return Status::InvalidArgument(where() + "tag " + std::to_string(tri.tag) +
                                     " does not exist");
  }
  for (const auto& [a, b] : tin.constraints) {
    if (a >= nv || b >= nv || a == b)
      return Status::InvalidArgument("constraint (" + std::to_string(a) + ", " + std::to_string(b) +
                                     ") is not an edge between two vertices");
  }
  return Status::Ok();
}

// 1 + the largest id in `table`, so a batch of rows can be given ids before it is written.
Result<int64_t> NextId(SqliteDb& db, const char* table) {
  TB_ASSIGN_OR_RETURN(int64_t max_id,
                      db.QueryInt(std::string("SELECT coalesce(max(id), 0) FROM ") + table));
  return max_id + 1;
}

// The store id of every tag value of `tin`, adding the values the dictionary lacks.
Result<std::vector<int64_t>> TagIds(SqliteDb& db, const Tin& tin) {
  std::vector<int64_t> ids;
  ids.reserve(tin.tags.size());
  for (const std::string& value : tin.tags) {
    TB_ASSIGN_OR_RETURN(
        Statement * insert,
        db.Cached("INSERT INTO tags(value) VALUES (?) ON CONFLICT(value) DO NOTHING"));
    TB_RETURN_IF_ERROR(insert->Bind(1, value).Run());
    TB_ASSIGN_OR_RETURN(Statement * select, db.Cached("SELECT id FROM tags WHERE value = ?"));
    select->Bind(1, value);
    TB_ASSIGN_OR_RETURN(bool row, select->Step());
    if (!row) return Status::Corruption("tag '" + value + "' vanished while being written");
    ids.push_back(select->ColumnInt(0));
    select->Reset();
  }
  return ids;
}

// 0..count-1 ordered by `less`, ties in index order.
template <typename Less>
std::vector<uint32_t> OrderBy(size_t count, Less less) {
  std::vector<uint32_t> order(count);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), less);
  return order;
}

}  // namespace

const char* SurfaceKindName(SurfaceKind kind) {
  return kind == SurfaceKind::kDelaunay ? "delaunay" : "free";
}

bool ParseSurfaceKind(const std::string& name, SurfaceKind* kind) {
  for (SurfaceKind k : {SurfaceKind::kDelaunay, SurfaceKind::kFree}) {
    if (name == SurfaceKindName(k)) {
      *kind = k;
      return true;
    }
  }
  return false;
}

int64_t CentroidBlock(const BlockGrid& grid, double ax, double ay, double bx, double by, double cx,
                      double cy) {
  return grid.BlockOf((ax + bx + cx) / 3.0, (ay + by + cy) / 3.0);
}

std::string SurfaceRowsInIdOrder(const std::string& table, const std::string& alias) {
  const std::string bound = "(id) FROM " + table + " WHERE surface = ?1)";
  return "WHERE " + alias + ".id BETWEEN (SELECT min" + bound + " AND (SELECT max" + bound +
         " AND +" + alias + ".surface = ?1 ORDER BY " + alias + ".id";
}

Result<std::unique_ptr<ReadSnapshot>> SnapshotUnlessInTransaction(Store& store) {
  if (sqlite3_get_autocommit(store.db().handle()) == 0) return std::unique_ptr<ReadSnapshot>();
  return ReadSnapshot::Begin(store);
}

Result<SurfaceInfo> SurfaceStore::Create(const SurfaceInfo& spec, const Tin& tin) {
  TB_RETURN_IF_ERROR(ValidateIndices(tin).WithContext("surface " + Quoted(spec.name)));
  SqliteDb& db = store_.db();
  {
    TB_ASSIGN_OR_RETURN(Statement * taken, db.Cached("SELECT 1 FROM surfaces WHERE name = ?"));
    taken->Bind(1, spec.name);
    TB_ASSIGN_OR_RETURN(bool exists, taken->Step());
    taken->Reset();
    if (exists) return Status::Conflict("surface " + Quoted(spec.name) + " already exists");
  }
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  for (const TinVertex& v : tin.vertices) {
    min_x = std::min(min_x, v.x);
    min_y = std::min(min_y, v.y);
    max_x = std::max(max_x, v.x);
    max_y = std::max(max_y, v.y);
  }
  if (tin.vertices.empty()) min_x = min_y = max_x = max_y = 0;

  SurfaceInfo info = spec;
  info.blocks =
      BlockGrid::For(min_x, min_y, max_x, max_y, static_cast<int64_t>(tin.triangles.size()));
  TB_ASSIGN_OR_RETURN(
      Statement * insert,
      db.Cached("INSERT INTO surfaces(name, kind, method, tolerance, dem, block_origin_x, "
                "block_origin_y, block_size) VALUES (?, ?, ?, ?, ?, ?, ?, ?)"));
  insert->Bind(1, info.name).Bind(2, std::string_view(SurfaceKindName(info.kind)));
  insert->Bind(3, info.method);
  if (info.tolerance)
    insert->Bind(4, *info.tolerance);
  else
    insert->BindNull(4);
  if (info.dem)
    insert->Bind(5, *info.dem);
  else
    insert->BindNull(5);
  insert->Bind(6, info.blocks.origin_x).Bind(7, info.blocks.origin_y).Bind(8, info.blocks.size);
  TB_RETURN_IF_ERROR(insert->Run().WithContext("creating surface " + Quoted(info.name)));
  info.id = db.LastInsertRowId();
  TB_RETURN_IF_ERROR(WriteRows(info, tin).status());
  return info;
}

Result<LoadedSurface> SurfaceStore::Replace(const SurfaceInfo& surface, const Tin& tin) {
  TB_RETURN_IF_ERROR(ValidateIndices(tin).WithContext("surface " + Quoted(surface.name)));
  SqliteDb& db = store_.db();
  for (const char* sql :
       {"DELETE FROM constraints WHERE surface = ?", "DELETE FROM triangles WHERE surface = ?",
        "DELETE FROM vertices WHERE surface = ?"}) {
    TB_ASSIGN_OR_RETURN(Statement * del, db.Cached(sql));
    TB_RETURN_IF_ERROR(del->Bind(1, surface.id).Run());
  }
  TB_ASSIGN_OR_RETURN(LoadedSurface out, WriteRows(surface, tin));
  out.tin = tin;
  return out;
}

Result<LoadedSurface> SurfaceStore::WriteRows(const SurfaceInfo& surface, const Tin& tin) {
  SqliteDb& db = store_.db();
  ScopedPageCache cache(db, tin.vertices.size() + tin.triangles.size());
  LoadedSurface out;
  TB_ASSIGN_OR_RETURN(const int64_t vertex_base, NextId(db, "vertices"));
  TB_ASSIGN_OR_RETURN(const int64_t triangle_base, NextId(db, "triangles"));
  TB_ASSIGN_OR_RETURN(const std::vector<int64_t> tag_ids, TagIds(db, tin));

  // Rows go in the order of their secondary index ((surface, x, y) and (surface, block)), so
  // each index insert appends at the right edge of its b-tree instead of seeking a random page:
  // bulk writes of millions of rows stay sequential. Ids are still consecutive, in that order.
  const std::vector<uint32_t> vertex_order =
      OrderBy(tin.vertices.size(), [&](uint32_t a, uint32_t b) {
        const TinVertex &p = tin.vertices[a], &q = tin.vertices[b];
        return p.x != q.x ? p.x < q.x : p.y < q.y;
      });
  std::vector<int64_t> blocks(tin.triangles.size());
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    const TinVertex& a = tin.vertices[tri.v[0]];
    const TinVertex& b = tin.vertices[tri.v[1]];
    const TinVertex& c = tin.vertices[tri.v[2]];
    blocks[t] = CentroidBlock(surface.blocks, a.x, a.y, b.x, b.y, c.x, c.y);
  }
  const std::vector<uint32_t> triangle_order =
      OrderBy(tin.triangles.size(), [&](uint32_t a, uint32_t b) { return blocks[a] < blocks[b]; });
  out.vertex_ids.resize(tin.vertices.size());
  for (size_t rank = 0; rank < vertex_order.size(); ++rank)
    out.vertex_ids[vertex_order[rank]] = vertex_base + static_cast<int64_t>(rank);
  out.triangle_ids.resize(tin.triangles.size());
  for (size_t rank = 0; rank < triangle_order.size(); ++rank)
    out.triangle_ids[triangle_order[rank]] = triangle_base + static_cast<int64_t>(rank);

  TB_ASSIGN_OR_RETURN(
      Statement * vertex,
      db.Cached("INSERT INTO vertices(id, surface, x, y, z, kind) VALUES (?, ?, ?, ?, ?, ?)"));
  for (uint32_t i : vertex_order) {
    const TinVertex& v = tin.vertices[i];
    vertex->Bind(1, out.vertex_ids[i]).Bind(2, surface.id).Bind(3, v.x).Bind(4, v.y).Bind(5, v.z);
    vertex->Bind(6, std::string_view(VertexKindName(v.kind)));
    if (Status s = vertex->Run(); !s.ok()) return s.WithContext("surface " + Quoted(surface.name));
  }

  TB_ASSIGN_OR_RETURN(
      Statement * triangle,
      db.Cached("INSERT INTO triangles(id, surface, v0, v1, v2, n0, n1, n2, visible, tag, block) "
                "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)"));
  for (uint32_t t : triangle_order) {
    const TinTriangle& tri = tin.triangles[t];
    triangle->Bind(1, out.triangle_ids[t]).Bind(2, surface.id);
    for (int i = 0; i < 3; ++i) {
      triangle->Bind(3 + i, out.vertex_ids[tri.v[i]]);
      if (tri.n[i] == kNoNeighbour)
        triangle->BindNull(6 + i);
      else
        triangle->Bind(6 + i, out.triangle_ids[tri.n[i]]);
    }
    triangle->Bind(9, int64_t{tri.visible ? 1 : 0});
    if (tri.tag == kNoTag)
      triangle->BindNull(10);
    else
      triangle->Bind(10, tag_ids[tri.tag]);
    triangle->Bind(11, blocks[t]);
    if (Status s = triangle->Run(); !s.ok())
      return s.WithContext("surface " + Quoted(surface.name));
  }

  TB_ASSIGN_OR_RETURN(Statement * constraint,
                      db.Cached("INSERT INTO constraints(surface, va, vb) VALUES (?, ?, ?)"));
  for (const auto& [a, b] : tin.constraints) {
    const int64_t va = out.vertex_ids[a], vb = out.vertex_ids[b];
    constraint->Bind(1, surface.id).Bind(2, std::min(va, vb)).Bind(3, std::max(va, vb));
    if (Status s = constraint->Run(); !s.ok())
      return s.WithContext("surface " + Quoted(surface.name));
  }
  return out;
}

Result<SurfaceInfo> SurfaceStore::FindWhere(const char* where,
                                            const std::function<void(Statement&)>& bind,
                                            const std::string& absent) {
  TB_ASSIGN_OR_RETURN(Statement * stmt, store_.db().Cached(std::string(kSurfaceColumns) + where));
  bind(*stmt);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  if (!row) return Status::NotFound(absent);
  SurfaceInfo info = SurfaceFromRow(*stmt);
  stmt->Reset();
  return info;
}

Result<SurfaceInfo> SurfaceStore::Find(const std::string& name) {
  return FindWhere(
      "WHERE name = ?", [&](Statement& s) { s.Bind(1, name); }, "no surface named " + Quoted(name));
}

Result<SurfaceInfo> SurfaceStore::FindById(int64_t id) {
  return FindWhere(
      "WHERE id = ?", [&](Statement& s) { s.Bind(1, id); },
      "no surface with id " + std::to_string(id));
}

Result<std::vector<SurfaceInfo>> SurfaceStore::List() {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store_.db().Cached(std::string(kSurfaceColumns) + "ORDER BY name"));
  std::vector<SurfaceInfo> out;
  for (;;) {
    TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
    if (!row) break;
    out.push_back(SurfaceFromRow(*stmt));
  }
  stmt->Reset();
  return out;
}

Result<SurfaceCounts> SurfaceStore::Count(const SurfaceInfo& surface) {
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      store_.db().Cached("SELECT (SELECT count(*) FROM vertices WHERE surface = ?1), "
                         "(SELECT count(*) FROM triangles WHERE surface = ?1), "
                         "(SELECT count(*) FROM triangles WHERE surface = ?1 AND visible = 1), "
                         "(SELECT count(*) FROM constraints WHERE surface = ?1), "
                         "(SELECT count(*) FROM features WHERE surface = ?1)"));
  stmt->Bind(1, surface.id);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  if (!row) return Status::Corruption("counting surface " + Quoted(surface.name) + ": no row");
  SurfaceCounts counts;
  counts.vertices = stmt->ColumnInt(0);
  counts.triangles = stmt->ColumnInt(1);
  counts.visible_triangles = stmt->ColumnInt(2);
  counts.constraints = stmt->ColumnInt(3);
  counts.features = stmt->ColumnInt(4);
  stmt->Reset();
  return counts;
}

Result<StoredTriangle> SurfaceStore::Triangle(const SurfaceInfo& surface, int64_t id) {
  TB_ASSIGN_OR_RETURN(Statement * stmt, store_.db().Cached(std::string(kTriangleColumns) +
                                                           "WHERE t.id = ? AND t.surface = ?"));
  stmt->Bind(1, id).Bind(2, surface.id);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  if (!row)
    return Status::NotFound("triangle " + std::to_string(id) + " is not in surface " +
                            Quoted(surface.name));
  StoredTriangle t = TriangleFromRow(*stmt);
  stmt->Reset();
  return t;
}

Result<StoredVertex> SurfaceStore::Vertex(const SurfaceInfo& surface, int64_t id) {
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      store_.db().Cached("SELECT x, y, z, kind FROM vertices WHERE id = ? AND surface = ?"));
  stmt->Bind(1, id).Bind(2, surface.id);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  if (!row)
    return Status::NotFound("vertex " + std::to_string(id) + " is not in surface " +
                            Quoted(surface.name));
  StoredVertex v;
  v.id = id;
  v.x = stmt->ColumnDouble(0);
  v.y = stmt->ColumnDouble(1);
  v.z = stmt->ColumnDouble(2);
  const std::string kind = stmt->ColumnText(3);
  stmt->Reset();
  if (!ParseVertexKind(kind, &v.kind))
    return Status::Corruption("surface " + Quoted(surface.name) + ", vertex " + std::to_string(id) +
                              ": unknown kind '" + kind + "'");
  return v;
}

Result<std::optional<int64_t>> SurfaceStore::AnyTriangleInBlock(const SurfaceInfo& surface,
                                                                int64_t block) {
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      store_.db().Cached("SELECT id FROM triangles WHERE surface = ? AND block = ? LIMIT 1"));
  stmt->Bind(1, surface.id).Bind(2, block);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  std::optional<int64_t> id;
  if (row) id = stmt->ColumnInt(0);
  stmt->Reset();
  return id;
}

Result<int64_t> SurfaceStore::AnyTriangle(const SurfaceInfo& surface) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store_.db().Cached("SELECT id FROM triangles WHERE surface = ? LIMIT 1"));
  stmt->Bind(1, surface.id);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  if (!row) return Status::NotFound("surface " + Quoted(surface.name) + " has no triangles");
  const int64_t id = stmt->ColumnInt(0);
  stmt->Reset();
  return id;
}

Result<LoadedSurface> SurfaceStore::Load(const SurfaceInfo& surface) {
  SqliteDb& db = store_.db();
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store_));
  const std::string where = "surface " + Quoted(surface.name);
  LoadedSurface out;
  std::unordered_map<int64_t, uint32_t> vertex_index;

  TB_ASSIGN_OR_RETURN(Statement * vertices,
                      db.Cached("SELECT id, x, y, z, kind FROM vertices " +
                                SurfaceRowsInIdOrder("vertices", "vertices")));
  vertices->Bind(1, surface.id);
  for (;;) {
    TB_ASSIGN_OR_RETURN(bool row, vertices->Step());
    if (!row) break;
    TinVertex v{vertices->ColumnDouble(1), vertices->ColumnDouble(2), vertices->ColumnDouble(3)};
    if (!ParseVertexKind(vertices->ColumnText(4), &v.kind))
      return Status::Corruption(where + ", vertex " + std::to_string(vertices->ColumnInt(0)) +
                                ": unknown kind '" + vertices->ColumnText(4) + "'");
    vertex_index.emplace(vertices->ColumnInt(0), static_cast<uint32_t>(out.tin.vertices.size()));
    out.vertex_ids.push_back(vertices->ColumnInt(0));
    out.tin.vertices.push_back(v);
  }
  vertices->Reset();

  TB_ASSIGN_OR_RETURN(Statement * triangles, db.Cached(std::string(kTriangleColumns) +
                                                       SurfaceRowsInIdOrder("triangles", "t")));
  triangles->Bind(1, surface.id);
  std::vector<StoredTriangle> rows;
  for (;;) {
    TB_ASSIGN_OR_RETURN(bool row, triangles->Step());
    if (!row) break;
    rows.push_back(TriangleFromRow(*triangles));
  }
  triangles->Reset();

  std::unordered_map<int64_t, int32_t> triangle_index;
  for (size_t t = 0; t < rows.size(); ++t) {
    triangle_index.emplace(rows[t].id, static_cast<int32_t>(t));
    out.triangle_ids.push_back(rows[t].id);
  }
  std::unordered_map<std::string, int32_t> tag_index;
  out.tin.triangles.reserve(rows.size());
  for (const StoredTriangle& row : rows) {
    TinTriangle tri;
    const std::string at = where + ", triangle " + std::to_string(row.id) + ": ";
    for (int i = 0; i < 3; ++i) {
      auto v = vertex_index.find(row.v[i]);
      if (v == vertex_index.end())
        return Status::Corruption(at + "vertex " + std::to_string(row.v[i]) + " is missing");
      tri.v[i] = v->second;
      if (!row.n[i]) continue;
      auto n = triangle_index.find(*row.n[i]);
      if (n == triangle_index.end())
        return Status::Corruption(at + "neighbour " + std::to_string(*row.n[i]) + " is missing");
      tri.n[i] = n->second;
    }
    tri.visible = row.visible;
    if (row.tag) {
      auto [it, added] = tag_index.emplace(*row.tag, static_cast<int32_t>(out.tin.tags.size()));
      if (added) out.tin.tags.push_back(*row.tag);
      tri.tag = it->second;
    }
    out.tin.triangles.push_back(tri);
  }

  TB_ASSIGN_OR_RETURN(
      Statement * constraints,
      db.Cached("SELECT va, vb FROM constraints WHERE surface = ? ORDER BY va, vb"));
  constraints->Bind(1, surface.id);
  for (;;) {
    TB_ASSIGN_OR_RETURN(bool row, constraints->Step());
    if (!row) break;
    const int64_t va = constraints->ColumnInt(0), vb = constraints->ColumnInt(1);
    auto a = vertex_index.find(va), b = vertex_index.find(vb);
    if (a == vertex_index.end() || b == vertex_index.end())
      return Status::Corruption(where + ": constraint (" + std::to_string(va) + ", " +
                                std::to_string(vb) + ") names a missing vertex");
    out.tin.constraints.emplace_back(a->second, b->second);
  }
  constraints->Reset();
  return out;
}

}  // namespace tinbase
