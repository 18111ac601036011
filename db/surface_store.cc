#include "db/surface_store.h"

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

#include "core/base/object_name.h"
#include "core/base/paged_id_map.h"
#include "db/mesh/mesh_tables.h"
#include "db/sql/large_write_hint.h"
#include "db/sql/unchecked_foreign_keys.h"

namespace tinbase {

namespace {

constexpr char kSurfaceColumns[] =
    "SELECT id, name, kind, method, tolerance, dem, block_origin_x, block_origin_y, block_size "
    "FROM surfaces ";

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
Result<SurfaceInfo> InsertSurfaceRow(Connection& db, const SurfaceInfo& spec,
                                     const BlockGrid& grid) {
  TB_RETURN_IF_ERROR(CheckObjectName("surface", spec.name));
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
                "block_origin_y, block_size) VALUES (?, ?, ?, ?, ?, ?, ?, ?) RETURNING id"));
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
  auto id = RunReturningId(*insert);
  if (!id.ok()) return id.status().WithContext("creating surface " + Quoted(info.name));
  info.id = *id;
  return info;
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

Result<std::unique_ptr<ReadSnapshot>> SnapshotUnlessInTransaction(Store& store) {
  if (store.db().InTransaction()) return std::unique_ptr<ReadSnapshot>();
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
  Connection& db = store_.db();
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
  LargeWriteHint cache(db, 3 * vertices.size());
  // Each row's surface is the row this write just made: SQLite's lookup of the parent for every
  // row would prove nothing (and costs a b-tree lookup per row).
  TB_ASSIGN_OR_RETURN(UncheckedForeignKeys unchecked, UncheckedForeignKeys::Begin(db));
  MeshTables mesh(db, info);
  TB_ASSIGN_OR_RETURN(const std::vector<int64_t> vertex_ids, mesh.InsertVertices(vertices));
  const int64_t first_vertex = vertex_ids.empty() ? 0 : vertex_ids[0];
  bool consecutive = true;
  for (size_t i = 0; i < vertex_ids.size() && consecutive; ++i)
    consecutive = vertex_ids[i] == first_vertex + static_cast<int64_t>(i);
  // The triangles of n points number at most 2n: their ids are reserved before the first batch
  // (the count is known only at the end), and any beyond the reservation below.
  const size_t reserved = 2 * vertices.size();
  TB_ASSIGN_OR_RETURN(const int64_t base, mesh.NextTriangleId(reserved));
  size_t written = 0;
  if (!started) group.wait();
  while (std::optional<TriangleBatch> batch = queue.Pop()) {
    TB_RETURN_IF_ERROR(ValidateBatch(*batch, vertices.size(), written)
                           .WithContext("surface " + Quoted(spec.name)));
    // A point import's vertices come sorted, so their ids are first_vertex + index.
    TB_RETURN_IF_ERROR(
        mesh.InsertTriangleBatch(*batch, base, first_vertex, consecutive ? nullptr : &vertex_ids));
    written += batch->triangles.size();
  }
  group.wait();
  // Past a reservation this write's ids ran on from it: a store write holds the whole store, so
  // the next reservation starts where this one ended, and these ids are taken from it.
  if (written > reserved) TB_RETURN_IF_ERROR(mesh.NextTriangleId(written - reserved).status());
  TB_RETURN_IF_ERROR(triangulated);
  return info;
}

Result<LoadedSurface> SurfaceStore::Replace(const SurfaceInfo& surface, const Tin& tin) {
  TB_RETURN_IF_ERROR(ValidateIndices(tin).WithContext("surface " + Quoted(surface.name)));
  TB_RETURN_IF_ERROR(MeshTables(store_.db(), surface).DeleteAll());
  TB_ASSIGN_OR_RETURN(LoadedSurface out, WriteRows(surface, tin));
  out.tin = tin;
  return out;
}

Result<LoadedSurface> SurfaceStore::WriteRows(const SurfaceInfo& surface, const Tin& tin) {
  Connection& db = store_.db();
  LargeWriteHint cache(db, tin.vertices.size() + tin.triangles.size());
  // As in CreateWhileTriangulating: every key was made sure of just before.
  TB_ASSIGN_OR_RETURN(UncheckedForeignKeys unchecked, UncheckedForeignKeys::Begin(db));
  MeshTables mesh(db, surface);
  LoadedSurface out;
  TB_ASSIGN_OR_RETURN(out.vertex_ids, mesh.InsertVertices(tin.vertices));
  TB_ASSIGN_OR_RETURN(out.triangle_ids, mesh.InsertTriangles(tin, out.vertex_ids));
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
  // A name that could never be stored names no surface. Asked as it is, PostgreSQL would cut
  // it at a NUL byte (and find "t" for "t\0evil") or refuse bytes that are not UTF-8.
  if (!CheckObjectName("surface", name).ok())
    return Status::NotFound("no surface named " + Quoted(name));
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
  TB_ASSIGN_OR_RETURN(const MeshCounts mesh, MeshTables(store_.db(), surface).Count());
  TB_ASSIGN_OR_RETURN(Statement * features,
                      store_.db().Cached("SELECT count(*) FROM features WHERE surface = ?"));
  features->Bind(1, surface.id);
  TB_ASSIGN_OR_RETURN(bool row, features->Step());
  if (!row) return Status::Corruption("counting surface " + Quoted(surface.name) + ": no row");
  SurfaceCounts counts;
  counts.vertices = mesh.vertices;
  counts.triangles = mesh.triangles;
  counts.visible_triangles = mesh.visible_triangles;
  counts.constraints = mesh.constraints;
  counts.features = features->ColumnInt(0);
  features->Reset();
  return counts;
}

Result<TriangleRow> SurfaceStore::Triangle(const SurfaceInfo& surface, int64_t id) {
  return MeshTables(store_.db(), surface).Triangle(id);
}

Result<VertexRow> SurfaceStore::Vertex(const SurfaceInfo& surface, int64_t id) {
  return MeshTables(store_.db(), surface).Vertex(id);
}

Result<std::string> SurfaceStore::TagValue(const SurfaceInfo& surface, int64_t tag) {
  return MeshTables(store_.db(), surface).TagValue(tag);
}

Result<std::optional<int64_t>> SurfaceStore::AnyTriangleInBlock(const SurfaceInfo& surface,
                                                                int64_t block) {
  return MeshTables(store_.db(), surface).AnyTriangleInBlock(block);
}

Result<int64_t> SurfaceStore::AnyTriangle(const SurfaceInfo& surface) {
  TB_ASSIGN_OR_RETURN(std::optional<int64_t> id, MeshTables(store_.db(), surface).AnyTriangle());
  if (!id) return Status::NotFound("surface " + Quoted(surface.name) + " has no triangles");
  return *id;
}

// A surface's rows read whole, phase by phase. Store id -> index maps are paged arrays: a
// surface's rows have runs of consecutive ids, so they hold an id in a few bytes where hash maps
// took ~40 (and a loaded surface's memory is first touched page fault by page fault). The phases
// fill `out` through a reference and keep their row loops whole: this is the load of the largest
// surfaces, and nothing here may add work per row.
namespace {

// The triangles as read, their neighbours still store ids.
struct StoredTriangles {
  PagedIdMap<int32_t> index;                                  // store id -> index in out.tin
  std::vector<std::array<std::optional<int64_t>, 3>> across;  // neighbour ids, resolved after
};

Status CorruptSurface(const SurfaceInfo& surface, const std::string& what) {
  return Status::Corruption("surface " + Quoted(surface.name) + what);
}

// Appends every vertex of `surface` to `out`; returns store id -> index into out.tin.vertices.
Result<PagedIdMap<uint32_t>> LoadVertices(MeshTables& mesh, const SurfaceInfo& surface,
                                          LoadedSurface& out) {
  PagedIdMap<uint32_t> vertex_index;
  TB_ASSIGN_OR_RETURN(VertexCursor vertices, mesh.Vertices());
  int64_t id = 0;
  TinVertex v;
  for (;;) {
    Result<bool> row = vertices.Next(&id, &v);
    if (!row.ok()) return row.status().WithContext("surface " + Quoted(surface.name));
    if (!*row) break;
    vertex_index.Put(id, static_cast<uint32_t>(out.tin.vertices.size()));
    out.vertex_ids.push_back(id);
    out.tin.vertices.push_back(v);
  }
  return vertex_index;
}

// Appends every triangle of `surface` to `out`, with its vertices and tag as indices; its
// neighbours are returned as store ids. Corruption naming a triangle whose vertex is missing.
Result<StoredTriangles> LoadTriangles(MeshTables& mesh, const SurfaceInfo& surface,
                                      const PagedIdMap<uint32_t>& vertex_index,
                                      LoadedSurface& out) {
  // Tags by id, read once: the tags table is small, and joining it row by row would carry a string
  // per triangle. A tag id not in it loads as no tag (`tinbase check` reports it: unknown-tag).
  TB_ASSIGN_OR_RETURN(const auto tag_values, mesh.TagValues());
  std::unordered_map<int64_t, int32_t> tag_index;  // tag id -> index into out.tin.tags

  StoredTriangles stored;
  TB_ASSIGN_OR_RETURN(TriangleCursor triangles, mesh.Triangles());
  int64_t id = 0;
  TriangleRow row;
  for (;;) {
    TB_ASSIGN_OR_RETURN(bool more, triangles.Next(&id, &row));
    if (!more) break;
    TinTriangle tri;
    for (int i = 0; i < 3; ++i) {
      const uint32_t* index = vertex_index.Find(row.v[i]);
      if (index == nullptr)
        return CorruptSurface(surface, ", triangle " + std::to_string(id) + ": vertex " +
                                           std::to_string(row.v[i]) + " is missing");
      tri.v[i] = *index;
    }
    stored.across.push_back(row.n);
    tri.visible = row.visible;
    if (row.tag) {
      auto known = tag_index.find(*row.tag);
      if (known == tag_index.end()) {
        auto value = tag_values.find(*row.tag);
        const int32_t index =
            value == tag_values.end() ? kNoTag : static_cast<int32_t>(out.tin.tags.size());
        if (value != tag_values.end()) out.tin.tags.push_back(value->second);
        known = tag_index.emplace(*row.tag, index).first;
      }
      tri.tag = known->second;
    }
    stored.index.Put(id, static_cast<int32_t>(out.tin.triangles.size()));
    out.triangle_ids.push_back(id);
    out.tin.triangles.push_back(tri);
  }
  return stored;
}

// Sets the neighbours of out.tin.triangles from their store ids; Corruption naming a triangle
// whose neighbour is missing.
Status ResolveNeighbours(const SurfaceInfo& surface, const StoredTriangles& stored,
                         LoadedSurface& out) {
  const auto& across = stored.across;
  for (size_t t = 0; t < across.size(); ++t) {
    for (int i = 0; i < 3; ++i) {
      if (!across[t][i]) continue;
      const int32_t* index = stored.index.Find(*across[t][i]);
      if (index == nullptr)
        return CorruptSurface(surface, ", triangle " + std::to_string(out.triangle_ids[t]) +
                                           ": neighbour " + std::to_string(*across[t][i]) +
                                           " is missing");
      out.tin.triangles[t].n[i] = *index;
    }
  }
  return Status::Ok();
}

// Appends every constraint of `surface` to out.tin.constraints; Corruption naming a constraint
// whose vertex is missing.
Status LoadConstraints(MeshTables& mesh, const SurfaceInfo& surface,
                       const PagedIdMap<uint32_t>& vertex_index, LoadedSurface& out) {
  TB_ASSIGN_OR_RETURN(ConstraintCursor constraints, mesh.Constraints());
  for (ConstraintRow c;;) {
    TB_ASSIGN_OR_RETURN(bool more, constraints.Next(&c));
    if (!more) break;
    const uint32_t* a = vertex_index.Find(c.va);
    const uint32_t* b = vertex_index.Find(c.vb);
    if (a == nullptr || b == nullptr)
      return CorruptSurface(surface, ": constraint (" + std::to_string(c.va) + ", " +
                                         std::to_string(c.vb) + ") names a missing vertex");
    out.tin.constraints.emplace_back(*a, *b);
  }
  return Status::Ok();
}

}  // namespace

Result<LoadedSurface> SurfaceStore::Load(const SurfaceInfo& surface) {
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store_));
  MeshTables mesh(store_.db(), surface);
  LoadedSurface out;
  TB_ASSIGN_OR_RETURN(const PagedIdMap<uint32_t> vertex_index, LoadVertices(mesh, surface, out));
  TB_ASSIGN_OR_RETURN(const StoredTriangles stored,
                      LoadTriangles(mesh, surface, vertex_index, out));
  TB_RETURN_IF_ERROR(ResolveNeighbours(surface, stored, out));
  TB_RETURN_IF_ERROR(LoadConstraints(mesh, surface, vertex_index, out));
  return out;
}

}  // namespace tinbase
