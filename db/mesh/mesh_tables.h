// MeshTables: the one module that holds the SQL of the mesh tables, `triangles`, `vertices` and
// `constraints` (and of `tags`, the dictionary the triangles' tag column points into), for one
// surface: reads by id, by block, by id range and of the whole surface, and the bulk writes of a
// surface's rows, and the writes of one edit. Everything else that reads or writes mesh rows
// (SurfaceStore, MeshCache, PointLocator, the integrity checker, feature exports, the edit's
// stages and its writer, db/edit/mesh_delta_writer.h) goes through it, with the row types of
// db/mesh/mesh_rows.h.
//
// Reads run on the connection's cached prepared statements, so a lookup by id costs one step of
// an already compiled query. Whole-surface reads scan the surface's rowid range (its rows are
// written with consecutive ids) instead of walking the surface index and sorting.
// Nothing here opens a transaction: a caller that reads several times holds a ReadSnapshot
// (SnapshotUnlessInTransaction) or a WriteTransaction around the calls; writes REQUIRE a
// WriteTransaction, whose rollback undoes a write that failed half way.
//
// Ownership: borrows the connection and the SurfaceInfo, which must outlive it; cheap to make
// (two references), so callers make one where they need it. Not thread-safe: one per thread, as
// the connection.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "core/tin/tin.h"
#include "core/tin/triangle_batch.h"
#include "db/mesh/mesh_edge.h"
#include "db/mesh/mesh_rows.h"
#include "db/sql/connection.h"

namespace tinbase {

struct SurfaceInfo;  // db/surface_store.h

// A forward read over the rows a MeshTables query selected, on its cached statement: at most one
// cursor of a query at a time (two would share the statement). Move-only; the statement is reset
// when the cursor ends or is destroyed.
class MeshCursor {
 public:
  MeshCursor(MeshCursor&& other) noexcept
      : stmt_(other.stmt_), surface_column_(other.surface_column_), surface_(other.surface_) {
    other.stmt_ = nullptr;
  }
  MeshCursor& operator=(MeshCursor&&) = delete;
  MeshCursor(const MeshCursor&) = delete;
  ~MeshCursor();

 protected:
  // `stmt` bound and not stepped yet. With surface_column >= 0 only the rows whose column
  // surface_column is `surface` are returned.
  explicit MeshCursor(Statement* stmt, int surface_column = -1, int64_t surface = 0)
      : stmt_(stmt), surface_column_(surface_column), surface_(surface) {}
  // Steps to the next row: true, or false past the last row (the statement is then reset, as
  // after an error). Errors of the store as Statement::Step returns them.
  Result<bool> Step();

  Statement* stmt_;  // null once the rows are read
  int surface_column_ = -1;
  int64_t surface_ = 0;
};

// Triangle rows with their ids.
class TriangleCursor : public MeshCursor {
 public:
  // The next row into *id, *row: true; false past the last row.
  Result<bool> Next(int64_t* id, TriangleRow* row);

 private:
  friend class MeshTables;
  using MeshCursor::MeshCursor;
};

// Vertex rows with their ids.
class VertexCursor : public MeshCursor {
 public:
  // The next row into *id, *row: true; false past the last row. Corruption naming the vertex
  // when its kind is not one of VertexKindName's spellings.
  Result<bool> Next(int64_t* id, VertexRow* row);

 private:
  friend class MeshTables;
  using MeshCursor::MeshCursor;
};

// Constraint rows.
class ConstraintCursor : public MeshCursor {
 public:
  // The next row into *row: true; false past the last row.
  Result<bool> Next(ConstraintRow* row);

 private:
  friend class MeshTables;
  using MeshCursor::MeshCursor;
};

// Row counts of one surface's mesh tables.
struct MeshCounts {
  int64_t vertices = 0;
  int64_t triangles = 0;
  int64_t visible_triangles = 0;
  int64_t constraints = 0;
};

class MeshTables {
 public:
  // REQUIRES: `db` and `surface` outlive this object.
  MeshTables(Connection& db, const SurfaceInfo& surface) : db_(db), surface_(surface) {}

  // ---- Reads by id. A missing row is NotFound naming the row and the surface; a caller that
  // followed a link to it reports Corruption in its own words (the link is what is wrong).

  Result<TriangleRow> Triangle(int64_t id);
  // Whether `id` is a triangle of the surface.
  Result<bool> HasTriangle(int64_t id);
  // Corruption also when the row's kind is unknown.
  Result<VertexRow> Vertex(int64_t id);
  // The value of tag `id`; NotFound when `tags` has no such row.
  Result<std::string> TagValue(int64_t id);
  // Every tag id and its value (the dictionary is small: read once instead of joined per row).
  Result<std::unordered_map<int64_t, std::string>> TagValues();

  // ---- Reads by block (the centroid grid of SurfaceInfo::blocks, through the (surface, block)
  // index).

  // Some triangle whose block is `block`, nullopt when none (the "jump" of jump-and-walk).
  Result<std::optional<int64_t>> AnyTriangleInBlock(int64_t block);
  // Some triangle of the surface, nullopt when it has none.
  Result<std::optional<int64_t>> AnyTriangle();
  // The ids of the triangles whose block is `block`, ascending.
  Result<std::vector<int64_t>> TriangleIdsInBlock(int64_t block);
  // The triangles whose packed block lies in [first, last] (BlockGrid::Pack: a run of blocks of
  // one grid row), by block, then id.
  Result<TriangleCursor> TrianglesInBlocks(int64_t first, int64_t last);
  // (id, block) of the triangles whose packed block lies in [first, last], in the order of the
  // (surface, block) index, which covers the query (no triangle row is read).
  Result<std::vector<std::pair<int64_t, int64_t>>> TriangleIdsAndBlocks(int64_t first,
                                                                        int64_t last);

  // ---- Reads of the whole surface, in id order (one scan of its rowid range each).

  Result<TriangleCursor> Triangles();
  Result<VertexCursor> Vertices();
  // Every constraint row, by (va, vb).
  Result<ConstraintCursor> Constraints();

  // ---- Reads by id range.

  // The surface's vertices with ids in [first, last], ascending. Selected by rowid alone: with
  // the surface in the WHERE clause SQLite may pick the surface index and scan every vertex of
  // the surface; the rows of other surfaces in the range are skipped here instead.
  Result<VertexCursor> VerticesInIdRange(int64_t first, int64_t last);
  // The constraint rows whose smaller vertex va lies in [first, last].
  Result<ConstraintCursor> ConstraintsFrom(int64_t first, int64_t last);
  // How many constraint rows have their smaller vertex in [first, last].
  Result<int64_t> CountConstraintsFrom(int64_t first, int64_t last);

  // ---- Reads of constraints by edge or feature.

  // The features owning the constraint rows of edge (va, vb), REQUIRES va < vb: one entry per
  // row, 0 for a row without feature; empty when the edge is not constrained.
  Result<std::vector<int64_t>> Owners(int64_t va, int64_t vb);
  // The constraint rows of `feature` in this surface.
  Result<std::vector<ConstraintRow>> ConstraintsOfFeature(int64_t feature);

  // Row counts of the surface.
  Result<MeshCounts> Count();
  Result<int64_t> CountConstraints();
  // The surface's triangle rows alone (one scan of the surface index, cheaper than Count()).
  Result<int64_t> CountTriangles();
  // min(CountTriangles(), limit), reading at most `limit` index entries: whether a surface is
  // small enough for a job, at a cost bounded by the job's size rather than the surface's.
  Result<int64_t> CountTrianglesUpTo(int64_t limit);

  // ---- Bulk writes. Each REQUIRES a WriteTransaction; an error leaves the rollback to it.

  // Writes `vertices` as rows of the surface with fresh consecutive ids, in x, then y order
  // (neighbouring vertices on neighbouring pages; the vertex index is by surface alone, which any
  // order of new ids appends to). Returns the id of each vertex by index.
  Result<std::vector<int64_t>> InsertVertices(const std::vector<TinVertex>& vertices);
  // Writes the triangles of `tin` (whose vertex i has id vertex_ids[i]) with fresh consecutive
  // ids in block order, so that every insert into the (surface, block) index appends at its
  // right edge instead of seeking a random page; adds the tag values the dictionary lacks, then
  // writes tin.constraints. Returns the id of each triangle by index. REQUIRES: the indices of
  // `tin` are valid (SurfaceStore validates them).
  Result<std::vector<int64_t>> InsertTriangles(const Tin& tin,
                                               const std::vector<int64_t>& vertex_ids);
  // The id the next triangle row written gets, the first of `count` reserved
  // (Connection::ReserveIds; on a single-writer store 1 + the largest in the table).
  Result<int64_t> NextTriangleId(size_t count);
  // Writes the rows of `batch`, triangle index t with id base + t, vertex index v with id
  // first_vertex + v, or vertex_ids[v] when `vertex_ids` is given; then fills in the neighbour
  // columns its links set in rows written before. The rows take the default paint (visible, no
  // tag). REQUIRES: `batch` was validated against the vertices and the rows written before it.
  Status InsertTriangleBatch(const TriangleBatch& batch, int64_t base, int64_t first_vertex,
                             const std::vector<int64_t>* vertex_ids);
  // Deletes every constraint, triangle and vertex row of the surface.
  Status DeleteAll();
  // Deletes the constraint rows of `feature` (of whatever surface).
  static Status DeleteConstraintsOfFeature(Connection& db, int64_t feature);

  // ---- Writes of one edit, the steps of db/edit/mesh_delta_writer.h (its only caller), each on
  // the connection's cached statements and the bulk statements of db/sql/bulk_write.h. Each
  // REQUIRES a WriteTransaction; an error leaves the rollback to it.

  // The id the next vertex row written gets, the first of `count` reserved (as NextTriangleId).
  Result<int64_t> NextVertexId(size_t count);
  // Writes `vertices` as rows of the surface with ids first_id, first_id + 1, ... in order.
  // REQUIRES: first_id == NextVertexId() in this transaction; Corruption, after the rows are
  // written, when they were numbered otherwise.
  Status AppendVertices(int64_t first_id, const std::vector<TinVertex>& vertices);
  // Sets the z of vertex v.id to v.vertex.z for each v (other columns stay).
  Status SetVertexZ(const std::vector<VertexZ>& vertices);
  // Writes `rows` as triangles of the surface with ids first_id, first_id + 1, ... in order,
  // paint and block as given. REQUIRES: first_id == NextTriangleId() in this transaction
  // (Corruption as AppendVertices otherwise); with foreign keys unchecked by the caller
  // (db/sql/unchecked_foreign_keys.h), every key the rows name exists.
  Status AppendTriangles(int64_t first_id, const std::vector<TriangleRow>& rows);
  // Deletes the surface's triangles with ids below `first_kept`; returns how many rows went.
  Result<int64_t> DeleteTrianglesBelow(int64_t first_kept);
  // Deletes the triangles `ids` (any order), one statement per run of consecutive ids: an edit's
  // region was mostly written together, in block order, so a run is often dozens of rows, and an
  // IN list of the ids of short runs cost more (SQLite builds a temporary table of it per
  // statement). Ids name rows of whatever surface (they are unique in the table).
  Status DeleteTriangles(std::vector<int64_t> ids);
  // Deletes the vertex rows `ids`.
  Status DeleteVertices(const std::vector<int64_t>& ids);
  // Sets the neighbour columns of triangle `id` to row.n for each (id, row) (other columns stay).
  // One UPDATE a row: cheaper than batches, whether REPLACE of whole rows or UPDATE ... FROM a
  // VALUES list.
  Status Relink(const std::vector<std::pair<int64_t, TriangleRow>>& rows);
  // Deletes the surface's constraint rows of each feature of `features`.
  Status DeleteConstraintsOfFeatures(const std::vector<int64_t>& features);
  // Deletes the surface's constraint rows of each edge (va, vb) of `edges`, va < vb.
  Status DeleteConstraints(const std::vector<MeshEdge>& edges);
  // Writes constraint rows of the surface: (edge (va, vb) with va < vb, feature; 0 for a row
  // without feature). Rows sorted by edge put the (surface, va, vb) index's entries in one sweep.
  Status InsertConstraints(const std::vector<std::pair<MeshEdge, int64_t>>& rows);
  // Gives the triangles `ids` the paint (visible, tag), up to 64 ids a statement; rows that have
  // it already are not rewritten. Returns how many rows changed.
  Result<int64_t> RepaintIds(bool visible, const std::optional<int64_t>& tag,
                             const std::vector<int64_t>& ids);
  // As RepaintIds for the triangles with ids in [first, last], in one statement walking the
  // table in id order (ids of whatever surface, as DeleteTriangles).
  Result<int64_t> RepaintRange(int64_t first, int64_t last, bool visible,
                               const std::optional<int64_t>& tag);

 private:
  std::string Where() const;  // "surface 'name'"

  Connection& db_;
  const SurfaceInfo& surface_;
};

}  // namespace tinbase
