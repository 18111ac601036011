#include "db/mesh/mesh_tables.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <utility>

#include "db/sql/bulk_write.h"
#include "db/surface_store.h"

namespace tinbase {

namespace {

std::string Quoted(const std::string& name) { return "'" + name + "'"; }

// The WHERE condition, with the surface as parameter ?1, that reads a surface's rows of `table`
// (vertices or triangles) in id order. A surface's rows are written with consecutive ids, so
// SQLite scans that rowid range instead of walking the (surface, ...) index and sorting a million
// rows. `alias` is how the query names the table.
std::string SurfaceRowsInIdOrder(const std::string& table, const std::string& alias) {
  const std::string bound = "(id) FROM " + table + " WHERE surface = ?1)";
  return "WHERE " + alias + ".id BETWEEN (SELECT min" + bound + " AND (SELECT max" + bound +
         " AND +" + alias + ".surface = ?1 ORDER BY " + alias + ".id";
}

// Every triangle read selects the columns "v0, v1, v2, n0, n1, n2, visible, tag, block" first, then
// the id when the query does not name it.
constexpr int kTriangleIdColumn = 9;

void DecodeTriangle(const Statement& row, TriangleRow* t) {
  for (int i = 0; i < 3; ++i) {
    t->v[i] = row.ColumnInt(i);
    t->n[i] = row.ColumnIsNull(3 + i) ? std::nullopt : std::optional<int64_t>(row.ColumnInt(3 + i));
  }
  t->visible = row.ColumnInt(6) != 0;
  t->tag = row.ColumnIsNull(7) ? std::nullopt : std::optional<int64_t>(row.ColumnInt(7));
  t->block = row.ColumnInt(8);
}

// Every vertex read selects the columns "x, y, z, kind", then "id, surface" when the query does not
// name them.
constexpr int kVertexIdColumn = 4;

// False when the kind column is not a kind's spelling (the table's CHECK forbids that).
bool DecodeVertex(const Statement& row, VertexRow* v) {
  v->x = row.ColumnDouble(0);
  v->y = row.ColumnDouble(1);
  v->z = row.ColumnDouble(2);
  return ParseVertexKind(row.ColumnText(3), &v->kind);
}

// Every constraint read selects the columns "va, vb, feature".

void DecodeConstraint(const Statement& row, ConstraintRow* c) {
  c->va = row.ColumnInt(0);
  c->vb = row.ColumnInt(1);
  c->feature = row.ColumnIsNull(2) ? std::nullopt : std::optional<int64_t>(row.ColumnInt(2));
}

// Column 0 of every row of the bound statement `stmt`, as integers; resets it.
Result<std::vector<int64_t>> FirstColumn(Statement& stmt) {
  std::vector<int64_t> values;
  for (;;) {
    TB_ASSIGN_OR_RETURN(bool row, stmt.Step());
    if (!row) break;
    values.push_back(stmt.ColumnInt(0));
  }
  stmt.Reset();
  return values;
}

// The first row's column 0 of the bound statement `stmt`, if any; resets it.
Result<std::optional<int64_t>> FirstValue(Statement& stmt) {
  TB_ASSIGN_OR_RETURN(bool row, stmt.Step());
  std::optional<int64_t> value;
  if (row) value = stmt.ColumnInt(0);
  stmt.Reset();
  return value;
}

// The store id of every tag value of `tin`, adding the values the dictionary lacks.
Result<std::vector<int64_t>> TagIds(Connection& db, const Tin& tin) {
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

// Rows go in an order that keeps neighbours together, with consecutive ids in that order.
// Triangles go by block, the order of their (surface, block) index, so each index insert appends
// at the right edge of its b-tree instead of seeking a random page: bulk writes of millions of
// rows stay sequential. Vertices go by x, then y (their index is by surface alone, which any
// order of new ids appends to): a builder's insertion order would scatter the vertices of one
// window over the whole table, so reading the window would touch a page per vertex.

// Vertex indices by x, then y, ties in index order. Point imports hand their vertices over in
// that order already (they sort them to drop duplicates), which one pass confirms.
std::vector<uint32_t> VertexOrder(const std::vector<TinVertex>& vertices) {
  std::vector<uint32_t> order(vertices.size());
  std::iota(order.begin(), order.end(), 0u);
  const auto less = [&](uint32_t a, uint32_t b) {
    const TinVertex &p = vertices[a], &q = vertices[b];
    return p.x != q.x ? p.x < q.x : p.y < q.y;
  };
  if (!std::is_sorted(order.begin(), order.end(), less))
    std::stable_sort(order.begin(), order.end(), less);
  return order;
}

// Where a Tin's triangle rows go: each triangle's block, and the order the rows are written in
// (by block, ties in index order).
struct TriangleLayout {
  BlockGrid grid;
  std::vector<int64_t> blocks;
  std::vector<uint32_t> order;
};

TriangleLayout LayOutTriangles(const BlockGrid& grid, const Tin& tin) {
  TriangleLayout layout{grid, std::vector<int64_t>(tin.triangles.size()), {}};
  // (block, index) pairs sort in place, cache-friendly, where sorting indices through a block
  // table jumps around memory; the index in the pair keeps ties in index order.
  std::vector<std::pair<int64_t, uint32_t>> keyed(tin.triangles.size());
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    const TinVertex& a = tin.vertices[tri.v[0]];
    const TinVertex& b = tin.vertices[tri.v[1]];
    const TinVertex& c = tin.vertices[tri.v[2]];
    layout.blocks[t] = CentroidBlock(grid, a.x, a.y, b.x, b.y, c.x, c.y);
    keyed[t] = {layout.blocks[t], static_cast<uint32_t>(t)};
  }
  std::sort(keyed.begin(), keyed.end());
  layout.order.reserve(keyed.size());
  for (const auto& [block, t] : keyed) layout.order.push_back(t);
  return layout;
}

// Writes the vertex rows of `surface` with fresh ids; returns the id of each vertex by index.
Result<std::vector<int64_t>> WriteVertexRows(Connection& db, const SurfaceInfo& surface,
                                             const std::vector<TinVertex>& vertices) {
  TB_ASSIGN_OR_RETURN(const int64_t base, NextId(db, "vertices", vertices.size()));
  const std::vector<uint32_t> order = VertexOrder(vertices);
  std::vector<int64_t> ids(vertices.size());
  for (size_t rank = 0; rank < order.size(); ++rank)
    ids[order[rank]] = base + static_cast<int64_t>(rank);
  TB_RETURN_IF_ERROR(InsertNumberedRows(db, "vertices(surface, x, y, z, kind)", 5, order.size(),
                                        base,
                                        [&](Statement& row, int p, size_t rank) {
                                          // In x order, vertices of a built TIN are read at
                                          // random: ask for one a few rows on meanwhile.
                                          if (rank + 8 < order.size())
                                            __builtin_prefetch(&vertices[order[rank + 8]]);
                                          const TinVertex& v = vertices[order[rank]];
                                          row.Bind(p, surface.id).Bind(p + 1, v.x);
                                          row.Bind(p + 2, v.y).Bind(p + 3, v.z);
                                          row.BindStaticText(p + 4, VertexKindName(v.kind));
                                        })
                         .WithContext("surface " + Quoted(surface.name)));
  return ids;
}

// A triangle row without its paint: visible and tag take the columns' defaults (1, NULL), as
// every triangle of a freshly built surface has them; two values fewer to bind and copy per row.
// The id is left to SQLite (InsertNumberedRows).
constexpr char kTriangleRow[] = "triangles(surface, v0, v1, v2, n0, n1, n2, block)";
constexpr char kTriangleRowWithPaint[] =
    "triangles(surface, v0, v1, v2, n0, n1, n2, block, visible, tag)";
constexpr int kTriangleRowValues = 8;

// A triangle row's values, gathered before they are bound.
struct TriangleRowValues {
  int64_t v[3] = {};
  int64_t n[3] = {};  // meaningful where has_n
  bool has_n[3] = {};
  int64_t block = 0;
  bool visible = true;
  int64_t tag = 0;  // meaningful where has_tag
  bool has_tag = false;
};

// `tri`'s row without its tag: its vertices through `vertex_id` and its neighbours through
// `triangle_id` (an index to a store id), none for kNoNeighbour.
template <typename VertexId, typename TriangleId>
TriangleRowValues ValuesOf(const TinTriangle& tri, int64_t block, const VertexId& vertex_id,
                           const TriangleId& triangle_id) {
  TriangleRowValues row;
  for (int i = 0; i < 3; ++i) {
    row.v[i] = vertex_id(tri.v[i]);
    row.has_n[i] = tri.n[i] != kNoNeighbour;
    if (row.has_n[i]) row.n[i] = triangle_id(tri.n[i]);
  }
  row.block = block;
  row.visible = tri.visible;
  return row;
}

// Binds the values of kTriangleRow, or of kTriangleRowWithPaint when `with_paint`, from
// parameter p on; NULL for a missing neighbour or tag.
void BindTriangleRow(Statement& stmt, int p, int64_t surface, const TriangleRowValues& row,
                     bool with_paint) {
  stmt.Bind(p, surface);
  for (int i = 0; i < 3; ++i) {
    stmt.Bind(p + 1 + i, row.v[i]);
    if (row.has_n[i])
      stmt.Bind(p + 4 + i, row.n[i]);
    else
      stmt.BindNull(p + 4 + i);
  }
  stmt.Bind(p + 7, row.block);
  if (!with_paint) return;
  stmt.Bind(p + kTriangleRowValues, int64_t{row.visible ? 1 : 0});
  if (row.has_tag)
    stmt.Bind(p + kTriangleRowValues + 1, row.tag);
  else
    stmt.BindNull(p + kTriangleRowValues + 1);
}

// Rows gathered kChunk at a time ahead of their binding. In layout (block) order a row's values
// come from random places of a large TIN: the triangle, its block, its vertices' and neighbours'
// ids. Read in a tight loop, many of those cache misses overlap; read between two calls into
// SQLite, hardly any did, and on a surface of millions of triangles the binding mostly waited for
// memory.
// REQUIRES: At is called with ranks in increasing order (as InsertNumberedRows does).
template <typename Row, typename Fill>
class GatheredRows {
 public:
  GatheredRows(size_t count, Fill fill) : count_(count), fill_(std::move(fill)) {}

  const Row& At(size_t rank) {
    if (rank < first_ || rank >= first_ + rows_.size()) Gather(rank);
    return rows_[rank - first_];
  }

 private:
  static constexpr size_t kChunk = 4096;

  void Gather(size_t first) {
    first_ = first;
    rows_.resize(std::min(kChunk, count_ - first));
    for (size_t i = 0; i < rows_.size(); ++i) fill_(first + i, &rows_[i]);
  }

  size_t count_;
  size_t first_ = 0;
  std::vector<Row> rows_;
  Fill fill_;
};

// Writes the triangle and constraint rows of `tin` for `surface`, whose vertices have the ids
// `vertex_ids`, laid out by `layout`; returns the id of each triangle by index.
Result<std::vector<int64_t>> WriteTriangleRows(Connection& db, const SurfaceInfo& surface,
                                               const Tin& tin,
                                               const std::vector<int64_t>& vertex_ids,
                                               const TriangleLayout& layout) {
  TB_ASSIGN_OR_RETURN(const int64_t base, NextId(db, "triangles", tin.triangles.size()));
  TB_ASSIGN_OR_RETURN(const std::vector<int64_t> tag_ids, TagIds(db, tin));
  const std::vector<uint32_t>& order = layout.order;
  std::vector<int64_t> ids(tin.triangles.size());
  for (size_t rank = 0; rank < order.size(); ++rank)
    ids[order[rank]] = base + static_cast<int64_t>(rank);
  const std::string context = "surface " + Quoted(surface.name);
  // A freshly built surface takes kTriangleRow, the rows without paint.
  const bool defaults =
      std::all_of(tin.triangles.begin(), tin.triangles.end(),
                  [](const TinTriangle& t) { return t.visible && t.tag == kNoTag; });
  const auto vertex_id = [&](uint32_t v) { return vertex_ids[v]; };
  const auto triangle_id = [&](int32_t t) { return ids[static_cast<size_t>(t)]; };
  const auto fill = [&](size_t rank, TriangleRowValues* row) {
    // The triangle a few rows on, so its misses overlap this row's.
    constexpr size_t kAhead = 8;
    if (rank + kAhead < order.size()) {
      __builtin_prefetch(&tin.triangles[order[rank + kAhead]]);
      __builtin_prefetch(&layout.blocks[order[rank + kAhead]]);
    }
    const uint32_t t = order[rank];
    const TinTriangle& tri = tin.triangles[t];
    *row = ValuesOf(tri, layout.blocks[t], vertex_id, triangle_id);
    row->has_tag = tri.tag != kNoTag;
    if (row->has_tag) row->tag = tag_ids[tri.tag];
  };
  GatheredRows<TriangleRowValues, decltype(fill)> rows(order.size(), fill);
  TB_RETURN_IF_ERROR(
      InsertNumberedRows(db, defaults ? kTriangleRow : kTriangleRowWithPaint,
                         defaults ? kTriangleRowValues : kTriangleRowValues + 2, order.size(), base,
                         [&](Statement& stmt, int p, size_t rank) {
                           BindTriangleRow(stmt, p, surface.id, rows.At(rank), !defaults);
                         })
          .WithContext(context));
  TB_RETURN_IF_ERROR(InsertRows(db, "constraints(surface, va, vb)", 3, tin.constraints.size(),
                                [&](Statement& row, int p, size_t c) {
                                  const auto& [a, b] = tin.constraints[c];
                                  const int64_t va = vertex_ids[a], vb = vertex_ids[b];
                                  row.Bind(p, surface.id).Bind(p + 1, std::min(va, vb));
                                  row.Bind(p + 2, std::max(va, vb));
                                })
                         .WithContext(context));
  return ids;
}

// Writes the rows of `batch` (triangle index t gets id base + t, vertex index v the id
// vertex_id(v)), then the neighbour columns its links fill in rows written before.
template <typename VertexId>
Status WriteTriangleBatch(Connection& db, const SurfaceInfo& surface, const TriangleBatch& batch,
                          int64_t base, const VertexId& vertex_id) {
  const auto triangle_id = [&](int32_t t) { return base + t; };
  const int64_t first = base + static_cast<int64_t>(batch.first);
  TB_RETURN_IF_ERROR(
      InsertNumberedRows(db, kTriangleRow, kTriangleRowValues, batch.triangles.size(), first,
                         [&](Statement& row, int p, size_t k) {
                           BindTriangleRow(
                               row, p, surface.id,
                               ValuesOf(batch.triangles[k], batch.keys[k], vertex_id, triangle_id),
                               /*with_paint=*/false);
                         })
          .WithContext("surface " + Quoted(surface.name)));
  for (const TriangleBatch::Link& link : batch.links) {
    static constexpr const char* kSetNeighbour[] = {"UPDATE triangles SET n0 = ? WHERE id = ?",
                                                    "UPDATE triangles SET n1 = ? WHERE id = ?",
                                                    "UPDATE triangles SET n2 = ? WHERE id = ?"};
    TB_ASSIGN_OR_RETURN(Statement * update, db.Cached(kSetNeighbour[link.slot]));
    update->Bind(1, triangle_id(link.neighbour)).Bind(2, base + link.triangle);
    TB_RETURN_IF_ERROR(update->Run());
  }
  return Status::Ok();
}

// An edit's triangle row: every column but the id, in this order.
constexpr char kEditedTriangleRow[] =
    "triangles(surface, v0, v1, v2, n0, n1, n2, visible, tag, block)";
constexpr int kEditedTriangleRowValues = 10;

// Binds the values of kEditedTriangleRow for `t` from parameter p on.
void BindEditedTriangleRow(Statement& row, int p, int64_t surface, const TriangleRow& t) {
  row.Bind(p, surface);
  for (int i = 0; i < 3; ++i) {
    row.Bind(p + 1 + i, t.v[i]);
    if (t.n[i])
      row.Bind(p + 4 + i, *t.n[i]);
    else
      row.BindNull(p + 4 + i);
  }
  row.Bind(p + 7, int64_t{t.visible ? 1 : 0});
  if (t.tag)
    row.Bind(p + 8, *t.tag);
  else
    row.BindNull(p + 8);
  row.Bind(p + 9, t.block);
}

// Binds a paint to ?1 (visible) and ?2 (tag).
void BindPaint(Statement& stmt, bool visible, const std::optional<int64_t>& tag) {
  stmt.Bind(1, int64_t{visible ? 1 : 0});
  if (tag)
    stmt.Bind(2, *tag);
  else
    stmt.BindNull(2);
}

}  // namespace

// ---- Cursors

MeshCursor::~MeshCursor() {
  if (stmt_ != nullptr) stmt_->Reset();
}

Result<bool> MeshCursor::Step() {
  if (stmt_ == nullptr) return false;
  for (;;) {
    Result<bool> row = stmt_->Step();
    if (!row.ok() || !*row) {
      stmt_->Reset();
      stmt_ = nullptr;
      return row;
    }
    if (surface_column_ < 0 || stmt_->ColumnInt(surface_column_) == surface_) return true;
  }
}

Result<bool> TriangleCursor::Next(int64_t* id, TriangleRow* row) {
  TB_ASSIGN_OR_RETURN(bool more, Step());
  if (!more) return false;
  *id = stmt_->ColumnInt(kTriangleIdColumn);
  DecodeTriangle(*stmt_, row);
  return true;
}

Result<bool> VertexCursor::Next(int64_t* id, VertexRow* row) {
  TB_ASSIGN_OR_RETURN(bool more, Step());
  if (!more) return false;
  *id = stmt_->ColumnInt(kVertexIdColumn);
  if (!DecodeVertex(*stmt_, row)) {
    const std::string kind = stmt_->ColumnText(3);
    stmt_->Reset();
    stmt_ = nullptr;
    return Status::Corruption("vertex " + std::to_string(*id) + ": unknown kind '" + kind + "'");
  }
  return true;
}

Result<bool> ConstraintCursor::Next(ConstraintRow* row) {
  TB_ASSIGN_OR_RETURN(bool more, Step());
  if (!more) return false;
  DecodeConstraint(*stmt_, row);
  return true;
}

// ---- Reads by id

std::string MeshTables::Where() const { return "surface " + Quoted(surface_.name); }

Result<TriangleRow> MeshTables::Triangle(int64_t id) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT v0, v1, v2, n0, n1, n2, visible, tag, block "
                                 "FROM triangles WHERE id = ? AND surface = ?"));
  stmt->Bind(1, id).Bind(2, surface_.id);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  if (!row) {
    stmt->Reset();
    return Status::NotFound("triangle " + std::to_string(id) + " is not in " + Where());
  }
  TriangleRow t;
  DecodeTriangle(*stmt, &t);
  stmt->Reset();
  return t;
}

Result<bool> MeshTables::HasTriangle(int64_t id) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT 1 FROM triangles WHERE id = ? AND surface = ?"));
  stmt->Bind(1, id).Bind(2, surface_.id);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  stmt->Reset();
  return row;
}

Result<VertexRow> MeshTables::Vertex(int64_t id) {
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      db_.Cached("SELECT x, y, z, kind FROM vertices WHERE id = ? AND surface = ?"));
  stmt->Bind(1, id).Bind(2, surface_.id);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  if (!row) {
    stmt->Reset();
    return Status::NotFound("vertex " + std::to_string(id) + " is not in " + Where());
  }
  VertexRow v;
  const bool known = DecodeVertex(*stmt, &v);
  const std::string kind = known ? std::string() : stmt->ColumnText(3);
  stmt->Reset();
  if (!known)
    return Status::Corruption(Where() + ", vertex " + std::to_string(id) + ": unknown kind '" +
                              kind + "'");
  return v;
}

Result<std::string> MeshTables::TagValue(int64_t id) {
  TB_ASSIGN_OR_RETURN(Statement * stmt, db_.Cached("SELECT value FROM tags WHERE id = ?"));
  stmt->Bind(1, id);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  if (!row) {
    stmt->Reset();
    return Status::NotFound("tag " + std::to_string(id) + " is not a row of tags");
  }
  std::string value = stmt->ColumnText(0);
  stmt->Reset();
  return value;
}

Result<std::unordered_map<int64_t, std::string>> MeshTables::TagValues() {
  TB_ASSIGN_OR_RETURN(Statement * stmt, db_.Cached("SELECT id, value FROM tags"));
  std::unordered_map<int64_t, std::string> values;
  for (;;) {
    TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
    if (!row) break;
    values.emplace(stmt->ColumnInt(0), stmt->ColumnText(1));
  }
  stmt->Reset();
  return values;
}

// ---- Reads by block

Result<std::optional<int64_t>> MeshTables::AnyTriangleInBlock(int64_t block) {
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      db_.Cached("SELECT id FROM triangles WHERE surface = ? AND block = ? LIMIT 1"));
  stmt->Bind(1, surface_.id).Bind(2, block);
  return FirstValue(*stmt);
}

Result<std::optional<int64_t>> MeshTables::AnyTriangle() {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT id FROM triangles WHERE surface = ? LIMIT 1"));
  stmt->Bind(1, surface_.id);
  return FirstValue(*stmt);
}

Result<std::vector<int64_t>> MeshTables::TriangleIdsInBlock(int64_t block) {
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      db_.Cached("SELECT id FROM triangles WHERE surface = ? AND block = ? ORDER BY id"));
  stmt->Bind(1, surface_.id).Bind(2, block);
  return FirstColumn(*stmt);
}

Result<TriangleCursor> MeshTables::TrianglesInBlocks(int64_t first, int64_t last) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT v0, v1, v2, n0, n1, n2, visible, tag, block, id "
                                 "FROM triangles WHERE surface = ? AND block BETWEEN ? AND ? "
                                 "ORDER BY block, id"));
  stmt->Bind(1, surface_.id).Bind(2, first).Bind(3, last);
  return TriangleCursor(stmt);
}

Result<std::vector<std::pair<int64_t, int64_t>>> MeshTables::TriangleIdsAndBlocks(int64_t first,
                                                                                  int64_t last) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT id, block FROM triangles WHERE surface = ? "
                                 "AND block BETWEEN ? AND ?"));
  stmt->Bind(1, surface_.id).Bind(2, first).Bind(3, last);
  std::vector<std::pair<int64_t, int64_t>> rows;
  for (;;) {
    TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
    if (!row) break;
    rows.emplace_back(stmt->ColumnInt(0), stmt->ColumnInt(1));
  }
  stmt->Reset();
  return rows;
}

// ---- Reads of the whole surface

Result<TriangleCursor> MeshTables::Triangles() {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT t.v0, t.v1, t.v2, t.n0, t.n1, t.n2, t.visible, t.tag, "
                                 "t.block, t.id FROM triangles t " +
                                 SurfaceRowsInIdOrder("triangles", "t")));
  stmt->Bind(1, surface_.id);
  return TriangleCursor(stmt);
}

Result<VertexCursor> MeshTables::Vertices() {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT v.x, v.y, v.z, v.kind, v.id FROM vertices v " +
                                 SurfaceRowsInIdOrder("vertices", "v")));
  stmt->Bind(1, surface_.id);
  return VertexCursor(stmt);
}

Result<ConstraintCursor> MeshTables::Constraints() {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT va, vb, feature FROM constraints WHERE surface = ? "
                                 "ORDER BY va, vb"));
  stmt->Bind(1, surface_.id);
  return ConstraintCursor(stmt);
}

// ---- Reads by id range

Result<VertexCursor> MeshTables::VerticesInIdRange(int64_t first, int64_t last) {
  // The order is asked for: SQLite's rowid scan gives it anyway, PostgreSQL's heap order (an
  // updated row moves to the table's end) does not.
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT x, y, z, kind, id, surface FROM vertices "
                                 "WHERE id BETWEEN ? AND ? ORDER BY id"));
  stmt->Bind(1, first).Bind(2, last);
  return VertexCursor(stmt, kVertexIdColumn + 1, surface_.id);
}

Result<ConstraintCursor> MeshTables::ConstraintsFrom(int64_t first, int64_t last) {
  TB_ASSIGN_OR_RETURN(Statement * stmt, db_.Cached("SELECT va, vb, feature FROM constraints "
                                                   "WHERE surface = ? AND va BETWEEN ? AND ?"));
  stmt->Bind(1, surface_.id).Bind(2, first).Bind(3, last);
  return ConstraintCursor(stmt);
}

Result<int64_t> MeshTables::CountConstraintsFrom(int64_t first, int64_t last) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT count(*) FROM constraints WHERE surface = ? AND "
                                 "va BETWEEN ? AND ?"));
  stmt->Bind(1, surface_.id).Bind(2, first).Bind(3, last);
  TB_ASSIGN_OR_RETURN(std::optional<int64_t> count, FirstValue(*stmt));
  return count.value_or(0);
}

// ---- Constraints by edge or feature, counts

Result<std::vector<int64_t>> MeshTables::Owners(int64_t va, int64_t vb) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT coalesce(feature, 0) FROM constraints WHERE "
                                 "surface = ? AND va = ? AND vb = ?"));
  stmt->Bind(1, surface_.id).Bind(2, va).Bind(3, vb);
  return FirstColumn(*stmt);
}

Result<std::vector<ConstraintRow>> MeshTables::ConstraintsOfFeature(int64_t feature) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT va, vb, feature FROM constraints WHERE surface = ? AND "
                                 "feature = ?"));
  stmt->Bind(1, surface_.id).Bind(2, feature);
  ConstraintCursor cursor(stmt);
  std::vector<ConstraintRow> rows;
  for (ConstraintRow row;;) {
    TB_ASSIGN_OR_RETURN(bool more, cursor.Next(&row));
    if (!more) break;
    rows.push_back(row);
  }
  return rows;
}

Result<MeshCounts> MeshTables::Count() {
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      db_.Cached("SELECT (SELECT count(*) FROM vertices WHERE surface = ?1), "
                 "(SELECT count(*) FROM triangles WHERE surface = ?1), "
                 "(SELECT count(*) FROM triangles WHERE surface = ?1 AND visible = 1), "
                 "(SELECT count(*) FROM constraints WHERE surface = ?1)"));
  stmt->Bind(1, surface_.id);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  if (!row) return Status::Corruption("counting " + Where() + ": no row");
  MeshCounts counts;
  counts.vertices = stmt->ColumnInt(0);
  counts.triangles = stmt->ColumnInt(1);
  counts.visible_triangles = stmt->ColumnInt(2);
  counts.constraints = stmt->ColumnInt(3);
  stmt->Reset();
  return counts;
}

Result<int64_t> MeshTables::CountConstraints() {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT count(*) FROM constraints WHERE surface = ?"));
  stmt->Bind(1, surface_.id);
  TB_ASSIGN_OR_RETURN(std::optional<int64_t> count, FirstValue(*stmt));
  return count.value_or(0);
}

Result<int64_t> MeshTables::CountTriangles() {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT count(*) FROM triangles WHERE surface = ?"));
  stmt->Bind(1, surface_.id);
  TB_ASSIGN_OR_RETURN(std::optional<int64_t> count, FirstValue(*stmt));
  return count.value_or(0);
}

Result<int64_t> MeshTables::CountTrianglesUpTo(int64_t limit) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_.Cached("SELECT count(*) FROM (SELECT 1 FROM triangles WHERE surface = ? "
                                 "LIMIT ?) AS capped"));
  stmt->Bind(1, surface_.id).Bind(2, limit);
  TB_ASSIGN_OR_RETURN(std::optional<int64_t> count, FirstValue(*stmt));
  return count.value_or(0);
}

// ---- Bulk writes

Result<std::vector<int64_t>> MeshTables::InsertVertices(const std::vector<TinVertex>& vertices) {
  return WriteVertexRows(db_, surface_, vertices);
}

Result<std::vector<int64_t>> MeshTables::InsertTriangles(const Tin& tin,
                                                         const std::vector<int64_t>& vertex_ids) {
  return WriteTriangleRows(db_, surface_, tin, vertex_ids, LayOutTriangles(surface_.blocks, tin));
}

Result<int64_t> MeshTables::NextTriangleId(size_t count) { return NextId(db_, "triangles", count); }

Status MeshTables::InsertTriangleBatch(const TriangleBatch& batch, int64_t base,
                                       int64_t first_vertex,
                                       const std::vector<int64_t>* vertex_ids) {
  // Two instantiations, so the common case (a point import's vertices come sorted, their ids
  // first_vertex + index) computes ids instead of looking them up in 8 bytes a vertex of memory
  // that a batch's triangles visit out of order.
  if (vertex_ids != nullptr)
    return WriteTriangleBatch(db_, surface_, batch, base,
                              [&](uint32_t v) { return (*vertex_ids)[v]; });
  return WriteTriangleBatch(db_, surface_, batch, base,
                            [&](uint32_t v) { return first_vertex + static_cast<int64_t>(v); });
}

Status MeshTables::DeleteAll() {
  for (const char* sql :
       {"DELETE FROM constraints WHERE surface = ?", "DELETE FROM triangles WHERE surface = ?",
        "DELETE FROM vertices WHERE surface = ?"}) {
    TB_ASSIGN_OR_RETURN(Statement * del, db_.Cached(sql));
    TB_RETURN_IF_ERROR(del->Bind(1, surface_.id).Run());
  }
  return Status::Ok();
}

Status MeshTables::DeleteConstraintsOfFeature(Connection& db, int64_t feature) {
  TB_ASSIGN_OR_RETURN(Statement * stmt, db.Cached("DELETE FROM constraints WHERE feature = ?"));
  stmt->Bind(1, feature);
  return stmt->Run();
}

// ---- Writes of one edit

Result<int64_t> MeshTables::NextVertexId(size_t count) { return NextId(db_, "vertices", count); }

Status MeshTables::AppendVertices(int64_t first_id, const std::vector<TinVertex>& vertices) {
  return InsertNumberedRows(db_, "vertices(surface, x, y, z, kind)", 5, vertices.size(), first_id,
                            [&](Statement& row, int p, size_t k) {
                              const TinVertex& v = vertices[k];
                              row.Bind(p, surface_.id).Bind(p + 1, v.x);
                              row.Bind(p + 2, v.y).Bind(p + 3, v.z);
                              row.BindStaticText(p + 4, VertexKindName(v.kind));
                            });
}

Status MeshTables::SetVertexZ(const std::vector<VertexZ>& vertices) {
  if (vertices.empty()) return Status::Ok();
  TB_ASSIGN_OR_RETURN(Statement * set_z, db_.Cached("UPDATE vertices SET z = ? WHERE id = ?"));
  for (const VertexZ& v : vertices)
    TB_RETURN_IF_ERROR(set_z->Bind(1, v.vertex.z).Bind(2, v.id).Run());
  return Status::Ok();
}

Status MeshTables::AppendTriangles(int64_t first_id, const std::vector<TriangleRow>& rows) {
  return InsertNumberedRows(db_, kEditedTriangleRow, kEditedTriangleRowValues, rows.size(),
                            first_id, [&](Statement& row, int p, size_t k) {
                              BindEditedTriangleRow(row, p, surface_.id, rows[k]);
                            });
}

Result<int64_t> MeshTables::DeleteTrianglesBelow(int64_t first_kept) {
  TB_ASSIGN_OR_RETURN(Statement * del,
                      db_.Cached("DELETE FROM triangles WHERE surface = ? AND id < ?"));
  TB_RETURN_IF_ERROR(del->Bind(1, surface_.id).Bind(2, first_kept).Run());
  return db_.Changes();
}

Status MeshTables::DeleteTriangles(std::vector<int64_t> ids) {
  std::sort(ids.begin(), ids.end());
  TB_ASSIGN_OR_RETURN(Statement * del,
                      db_.Cached("DELETE FROM triangles WHERE id BETWEEN ? AND ?"));
  for (size_t first = 0; first < ids.size();) {
    size_t last = first;
    while (last + 1 < ids.size() && ids[last + 1] == ids[last] + 1) ++last;
    TB_RETURN_IF_ERROR(del->Bind(1, ids[first]).Bind(2, ids[last]).Run());
    first = last + 1;
  }
  return Status::Ok();
}

Status MeshTables::DeleteVertices(const std::vector<int64_t>& ids) {
  TB_ASSIGN_OR_RETURN(Statement * del_vertex, db_.Cached("DELETE FROM vertices WHERE id = ?"));
  for (int64_t v : ids) TB_RETURN_IF_ERROR(del_vertex->Bind(1, v).Run());
  return Status::Ok();
}

Status MeshTables::Relink(const std::vector<std::pair<int64_t, TriangleRow>>& rows) {
  TB_ASSIGN_OR_RETURN(Statement * relink,
                      db_.Cached("UPDATE triangles SET n0 = ?, n1 = ?, n2 = ? WHERE id = ?"));
  for (const auto& [id, t] : rows) {
    for (int i = 0; i < 3; ++i) {
      if (t.n[i])
        relink->Bind(1 + i, *t.n[i]);
      else
        relink->BindNull(1 + i);
    }
    TB_RETURN_IF_ERROR(relink->Bind(4, id).Run());
  }
  return Status::Ok();
}

Status MeshTables::DeleteConstraintsOfFeatures(const std::vector<int64_t>& features) {
  TB_ASSIGN_OR_RETURN(Statement * del_feature,
                      db_.Cached("DELETE FROM constraints WHERE surface = ? AND feature = ?"));
  for (int64_t f : features) TB_RETURN_IF_ERROR(del_feature->Bind(1, surface_.id).Bind(2, f).Run());
  return Status::Ok();
}

Status MeshTables::DeleteConstraints(const std::vector<MeshEdge>& edges) {
  TB_ASSIGN_OR_RETURN(
      Statement * del_edge,
      db_.Cached("DELETE FROM constraints WHERE surface = ? AND va = ? AND vb = ?"));
  for (const MeshEdge& e : edges)
    TB_RETURN_IF_ERROR(del_edge->Bind(1, surface_.id).Bind(2, e.first).Bind(3, e.second).Run());
  return Status::Ok();
}

Status MeshTables::InsertConstraints(const std::vector<std::pair<MeshEdge, int64_t>>& rows) {
  return InsertRows(db_, "constraints(surface, va, vb, feature)", 4, rows.size(),
                    [&](Statement& row, int p, size_t c) {
                      const auto& [e, feature] = rows[c];
                      row.Bind(p, surface_.id).Bind(p + 1, e.first);
                      row.Bind(p + 2, e.second);
                      if (feature != 0)
                        row.Bind(p + 3, feature);
                      else
                        row.BindNull(p + 3);
                    });
}

Result<int64_t> MeshTables::RepaintIds(bool visible, const std::optional<int64_t>& tag,
                                       const std::vector<int64_t>& ids) {
  int64_t repainted = 0;
  TB_RETURN_IF_ERROR(RunOverIds(
      db_, "UPDATE triangles SET visible = ?1, tag = ?2 WHERE id IN",
      " AND (visible IS DISTINCT FROM ?1 OR tag IS DISTINCT FROM ?2)", 2, ids,
      [&](Statement& stmt) { BindPaint(stmt, visible, tag); }, &repainted));
  return repainted;
}

Result<int64_t> MeshTables::RepaintRange(int64_t first, int64_t last, bool visible,
                                         const std::optional<int64_t>& tag) {
  TB_ASSIGN_OR_RETURN(Statement * repaint_run,
                      db_.Cached("UPDATE triangles SET visible = ?1, tag = ?2 WHERE "
                                 "id BETWEEN ?3 AND ?4 AND "
                                 "(visible IS DISTINCT FROM ?1 OR tag IS DISTINCT FROM ?2)"));
  BindPaint(*repaint_run, visible, tag);
  TB_RETURN_IF_ERROR(repaint_run->Bind(3, first).Bind(4, last).Run());
  return db_.Changes();
}

}  // namespace tinbase
