#include "db/surface_store.h"

#include <sqlite3.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <limits>
#include <mutex>
#include <numeric>
#include <optional>
#include <unordered_map>

#include "core/base/paged_id_map.h"
#include "db/sqlite/bulk_write.h"
#include "db/sqlite/scoped_page_cache.h"
#include "db/sqlite/unchecked_foreign_keys.h"

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

// The block grid of a surface with `triangles` triangles over `vertices`.
BlockGrid GridFor(const std::vector<TinVertex>& vertices, size_t triangles) {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  for (const TinVertex& v : vertices) {
    min_x = std::min(min_x, v.x);
    min_y = std::min(min_y, v.y);
    max_x = std::max(max_x, v.x);
    max_y = std::max(max_y, v.y);
  }
  if (vertices.empty()) min_x = min_y = max_x = max_y = 0;
  return BlockGrid::For(min_x, min_y, max_x, max_y, static_cast<int64_t>(triangles));
}

// Inserts the surfaces row of `spec` with block grid `grid`; returns spec with id and grid.
// Conflict when the name is taken.
Result<SurfaceInfo> InsertSurfaceRow(SqliteDb& db, const SurfaceInfo& spec, const BlockGrid& grid) {
  {
    TB_ASSIGN_OR_RETURN(Statement * taken, db.Cached("SELECT 1 FROM surfaces WHERE name = ?"));
    taken->Bind(1, spec.name);
    TB_ASSIGN_OR_RETURN(bool exists, taken->Step());
    taken->Reset();
    if (exists) return Status::Conflict("surface " + Quoted(spec.name) + " already exists");
  }
  SurfaceInfo info = spec;
  info.blocks = grid;
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
  return info;
}

// Writes the vertex rows of `surface` with fresh ids; returns the id of each vertex by index.
Result<std::vector<int64_t>> WriteVertexRows(SqliteDb& db, const SurfaceInfo& surface,
                                             const std::vector<TinVertex>& vertices) {
  TB_ASSIGN_OR_RETURN(const int64_t base, NextId(db, "vertices"));
  const std::vector<uint32_t> order = VertexOrder(vertices);
  std::vector<int64_t> ids(vertices.size());
  for (size_t rank = 0; rank < order.size(); ++rank)
    ids[order[rank]] = base + static_cast<int64_t>(rank);
  TB_RETURN_IF_ERROR(InsertNumberedRows(db, "vertices(surface, x, y, z, kind)", 5, order.size(),
                                        base, [&](Statement& row, int p, size_t rank) {
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
// SQLite, hardly any did (on a 4.09 M-triangle surface the binding waited ~2 s for memory).
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
Result<std::vector<int64_t>> WriteTriangleRows(SqliteDb& db, const SurfaceInfo& surface,
                                               const Tin& tin,
                                               const std::vector<int64_t>& vertex_ids,
                                               const TriangleLayout& layout) {
  TB_ASSIGN_OR_RETURN(const int64_t base, NextId(db, "triangles"));
  TB_ASSIGN_OR_RETURN(const std::vector<int64_t> tag_ids, TagIds(db, tin));
  const std::vector<uint32_t>& order = layout.order;
  std::vector<int64_t> ids(tin.triangles.size());
  for (size_t rank = 0; rank < order.size(); ++rank)
    ids[order[rank]] = base + static_cast<int64_t>(rank);
  const std::string context = "surface " + Quoted(surface.name);
  // A freshly built surface takes kTriangleRow, the rows without paint.
  const bool defaults = std::all_of(tin.triangles.begin(), tin.triangles.end(),
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
                         defaults ? kTriangleRowValues : kTriangleRowValues + 2, order.size(),
                         base, [&](Statement& stmt, int p, size_t rank) {
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

// Batches from the triangulating task to the writing thread, in order.
class BatchQueue {
 public:
  void Push(TriangleBatch batch) {
    {
      std::lock_guard<std::mutex> lock(mu_);
      batches_.push_back(std::move(batch));
    }
    ready_.notify_one();
  }
  // No batch follows.
  void Close() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      closed_ = true;
    }
    ready_.notify_one();
  }
  // The next batch, waiting for it; nullopt once the queue is closed and empty.
  std::optional<TriangleBatch> Pop() {
    std::unique_lock<std::mutex> lock(mu_);
    ready_.wait(lock, [&] { return closed_ || !batches_.empty(); });
    if (batches_.empty()) return std::nullopt;
    TriangleBatch batch = std::move(batches_.front());
    batches_.pop_front();
    return batch;
  }

 private:
  std::mutex mu_;
  std::condition_variable ready_;
  std::deque<TriangleBatch> batches_;
  bool closed_ = false;
};

// InvalidArgument naming the first index of `batch` that cannot be right: a vertex of none of the
// `vertices`, a neighbour or link outside the triangles handed over so far, a batch that does
// not continue at `written`.
Status ValidateBatch(const TriangleBatch& batch, size_t vertices, size_t written) {
  const size_t end = written + batch.triangles.size();
  if (batch.first != written || batch.keys.size() != batch.triangles.size())
    return Status::InvalidArgument("triangle batch at " + std::to_string(batch.first) +
                                   " does not follow the " + std::to_string(written) +
                                   " triangles written");
  const auto known = [&](int64_t t) { return t >= 0 && static_cast<size_t>(t) < end; };
  for (size_t k = 0; k < batch.triangles.size(); ++k) {
    const TinTriangle& tri = batch.triangles[k];
    for (int i = 0; i < 3; ++i) {
      if (tri.v[i] >= vertices || (tri.n[i] != kNoNeighbour && !known(tri.n[i])))
        return Status::InvalidArgument("triangle " + std::to_string(written + k) +
                                       ": a vertex or neighbour does not exist");
    }
  }
  for (const TriangleBatch::Link& link : batch.links) {
    if (link.triangle >= written || link.slot < 0 || link.slot > 2 || !known(link.neighbour))
      return Status::InvalidArgument("triangle " + std::to_string(link.triangle) +
                                     ": a late neighbour link does not fit");
  }
  return Status::Ok();
}

// Writes the rows of `batch` (triangle index t gets id base + t, vertex index v the id
// vertex_id(v)), then the neighbour columns its links fill in rows written before.
template <typename VertexId>
Status WriteTriangleBatch(SqliteDb& db, const SurfaceInfo& surface, const TriangleBatch& batch,
                          int64_t base, const VertexId& vertex_id) {
  const auto triangle_id = [&](int32_t t) { return base + t; };
  const int64_t first = base + static_cast<int64_t>(batch.first);
  TB_RETURN_IF_ERROR(InsertNumberedRows(db, kTriangleRow, kTriangleRowValues,
                                        batch.triangles.size(), first,
                                        [&](Statement& row, int p, size_t k) {
                                          BindTriangleRow(row, p, surface.id,
                                                          ValuesOf(batch.triangles[k],
                                                                   batch.keys[k], vertex_id,
                                                                   triangle_id),
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
  TB_ASSIGN_OR_RETURN(
      SurfaceInfo info,
      InsertSurfaceRow(store_.db(), spec, GridFor(tin.vertices, tin.triangles.size())));
  TB_RETURN_IF_ERROR(WriteRows(info, tin).status());
  return info;
}

Result<SurfaceInfo> SurfaceStore::CreateWhileTriangulating(
    const SurfaceInfo& spec, const std::vector<TinVertex>& vertices,
    const BatchedTriangulation& triangulate) {
  SqliteDb& db = store_.db();
  // n points in general position have 2n - 2 - h Delaunay triangles (h on the convex hull): the
  // grid is sized for 2n, as rows are written before the count is known.
  TB_ASSIGN_OR_RETURN(SurfaceInfo info,
                      InsertSurfaceRow(db, spec, GridFor(vertices, 2 * vertices.size())));
  const BlockGrid grid = info.blocks;
  BatchQueue queue;
  Status triangulated;
  std::atomic<bool> started{false};
  // A TBB task triangulates. It is waited for on every return path (WaitOnExit), so what it
  // uses outlives it; when no thread took it up (one thread allowed), it runs here before the
  // first batch is read (below), its batches waiting in the queue.
  tbb::task_group group;
  struct WaitOnExit {
    tbb::task_group& group;
    ~WaitOnExit() { group.wait(); }
  } wait_on_exit{group};
  group.run([&] {
    started = true;
    const auto block = [&](const TinTriangle& t) {
      const TinVertex &a = vertices[t.v[0]], &b = vertices[t.v[1]], &c = vertices[t.v[2]];
      return CentroidBlock(grid, a.x, a.y, b.x, b.y, c.x, c.y);
    };
    triangulated = triangulate(block, [&](TriangleBatch batch) { queue.Push(std::move(batch)); });
    queue.Close();
  });
  ScopedPageCache cache(db, 3 * vertices.size());
  // Each row's surface is the row this write just made: SQLite's lookup of the parent for every
  // row would prove nothing (it is about 10 % of a row's cost).
  TB_ASSIGN_OR_RETURN(UncheckedForeignKeys unchecked, UncheckedForeignKeys::Begin(db));
  TB_ASSIGN_OR_RETURN(const std::vector<int64_t> vertex_ids, WriteVertexRows(db, info, vertices));
  const int64_t first_vertex = vertex_ids.empty() ? 0 : vertex_ids[0];
  bool consecutive = true;
  for (size_t i = 0; i < vertex_ids.size() && consecutive; ++i)
    consecutive = vertex_ids[i] == first_vertex + static_cast<int64_t>(i);
  TB_ASSIGN_OR_RETURN(const int64_t base, NextId(db, "triangles"));
  size_t written = 0;
  if (!started) group.wait();
  while (std::optional<TriangleBatch> batch = queue.Pop()) {
    TB_RETURN_IF_ERROR(ValidateBatch(*batch, vertices.size(), written)
                           .WithContext("surface " + Quoted(spec.name)));
    // A point import's vertices come sorted, so their ids are first_vertex + index: computed, not
    // looked up in 8 bytes a vertex of memory that a batch's triangles visit out of order.
    TB_RETURN_IF_ERROR(
        consecutive
            ? WriteTriangleBatch(db, info, *batch, base,
                                 [&](uint32_t v) { return first_vertex + static_cast<int64_t>(v); })
            : WriteTriangleBatch(db, info, *batch, base,
                                 [&](uint32_t v) { return vertex_ids[v]; }));
    written += batch->triangles.size();
  }
  group.wait();
  TB_RETURN_IF_ERROR(triangulated);
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
  // As in CreateWhileTriangulating: every key was made sure of just before.
  TB_ASSIGN_OR_RETURN(UncheckedForeignKeys unchecked, UncheckedForeignKeys::Begin(db));
  LoadedSurface out;
  TB_ASSIGN_OR_RETURN(out.vertex_ids, WriteVertexRows(db, surface, tin.vertices));
  TB_ASSIGN_OR_RETURN(out.triangle_ids, WriteTriangleRows(db, surface, tin, out.vertex_ids,
                                                          LayOutTriangles(surface.blocks, tin)));
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
  const auto corrupt = [&](const std::string& what) {
    return Status::Corruption("surface " + Quoted(surface.name) + what);
  };
  LoadedSurface out;
  // Store id -> index. A surface's rows have runs of consecutive ids, so paged arrays hold this in
  // a few bytes an id where hash maps took ~40 (and a loaded surface's memory is first touched
  // page fault by page fault).
  PagedIdMap<uint32_t> vertex_index;
  PagedIdMap<int32_t> triangle_index;

  TB_ASSIGN_OR_RETURN(Statement * vertices,
                      db.Cached("SELECT id, x, y, z, kind FROM vertices " +
                                SurfaceRowsInIdOrder("vertices", "vertices")));
  vertices->Bind(1, surface.id);
  for (;;) {
    TB_ASSIGN_OR_RETURN(bool row, vertices->Step());
    if (!row) break;
    const int64_t id = vertices->ColumnInt(0);
    TinVertex v{vertices->ColumnDouble(1), vertices->ColumnDouble(2), vertices->ColumnDouble(3)};
    if (!ParseVertexKind(vertices->ColumnText(4), &v.kind))
      return corrupt(", vertex " + std::to_string(id) + ": unknown kind '" +
                     vertices->ColumnText(4) + "'");
    vertex_index.Put(id, static_cast<uint32_t>(out.tin.vertices.size()));
    out.vertex_ids.push_back(id);
    out.tin.vertices.push_back(v);
  }
  vertices->Reset();

  // Tags by id, read once: the tags table is small, and joining it row by row would carry a string
  // per triangle. A tag id not in it loads as no tag (`tinbase check` reports it: unknown-tag).
  std::unordered_map<int64_t, std::string> tag_values;
  TB_ASSIGN_OR_RETURN(Statement * tags, db.Cached("SELECT id, value FROM tags"));
  for (;;) {
    TB_ASSIGN_OR_RETURN(bool row, tags->Step());
    if (!row) break;
    tag_values.emplace(tags->ColumnInt(0), tags->ColumnText(1));
  }
  tags->Reset();
  std::unordered_map<int64_t, int32_t> tag_index;  // tag id -> index into out.tin.tags

  TB_ASSIGN_OR_RETURN(
      Statement * triangles,
      db.Cached("SELECT t.id, t.v0, t.v1, t.v2, t.n0, t.n1, t.n2, t.visible, t.tag FROM "
                "triangles t " +
                SurfaceRowsInIdOrder("triangles", "t")));
  triangles->Bind(1, surface.id);
  std::vector<std::array<std::optional<int64_t>, 3>> across;  // neighbour ids, resolved below
  for (;;) {
    TB_ASSIGN_OR_RETURN(bool row, triangles->Step());
    if (!row) break;
    const int64_t id = triangles->ColumnInt(0);
    TinTriangle tri;
    std::array<std::optional<int64_t>, 3>& n = across.emplace_back();
    for (int i = 0; i < 3; ++i) {
      const int64_t v = triangles->ColumnInt(1 + i);
      const uint32_t* index = vertex_index.Find(v);
      if (index == nullptr)
        return corrupt(", triangle " + std::to_string(id) + ": vertex " + std::to_string(v) +
                       " is missing");
      tri.v[i] = *index;
      if (!triangles->ColumnIsNull(4 + i)) n[i] = triangles->ColumnInt(4 + i);
    }
    tri.visible = triangles->ColumnInt(7) != 0;
    if (!triangles->ColumnIsNull(8)) {
      const int64_t tag = triangles->ColumnInt(8);
      auto known = tag_index.find(tag);
      if (known == tag_index.end()) {
        auto value = tag_values.find(tag);
        const int32_t index =
            value == tag_values.end() ? kNoTag : static_cast<int32_t>(out.tin.tags.size());
        if (value != tag_values.end()) out.tin.tags.push_back(value->second);
        known = tag_index.emplace(tag, index).first;
      }
      tri.tag = known->second;
    }
    triangle_index.Put(id, static_cast<int32_t>(out.tin.triangles.size()));
    out.triangle_ids.push_back(id);
    out.tin.triangles.push_back(tri);
  }
  triangles->Reset();
  for (size_t t = 0; t < across.size(); ++t) {
    for (int i = 0; i < 3; ++i) {
      if (!across[t][i]) continue;
      const int32_t* index = triangle_index.Find(*across[t][i]);
      if (index == nullptr)
        return corrupt(", triangle " + std::to_string(out.triangle_ids[t]) + ": neighbour " +
                       std::to_string(*across[t][i]) + " is missing");
      out.tin.triangles[t].n[i] = *index;
    }
  }

  TB_ASSIGN_OR_RETURN(
      Statement * constraints,
      db.Cached("SELECT va, vb FROM constraints WHERE surface = ? ORDER BY va, vb"));
  constraints->Bind(1, surface.id);
  for (;;) {
    TB_ASSIGN_OR_RETURN(bool row, constraints->Step());
    if (!row) break;
    const int64_t va = constraints->ColumnInt(0), vb = constraints->ColumnInt(1);
    const uint32_t* a = vertex_index.Find(va);
    const uint32_t* b = vertex_index.Find(vb);
    if (a == nullptr || b == nullptr)
      return corrupt(": constraint (" + std::to_string(va) + ", " + std::to_string(vb) +
                     ") names a missing vertex");
    out.tin.constraints.emplace_back(*a, *b);
  }
  constraints->Reset();
  return out;
}

}  // namespace tinbase
