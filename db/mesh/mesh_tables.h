// MeshTables: the one module that holds the SQL of the mesh tables, `triangles`, `vertices` and
// `constraints` (and of `tags`, the dictionary the triangles' tag column points into), for one
// surface: reads by id, by block, by id range and of the whole surface, and the bulk writes of a
// surface's rows. Everything else that reads or writes mesh rows (SurfaceStore, MeshCache,
// PointLocator, the integrity checker, feature exports) goes through it, with the row types of
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
#include <vector>

#include "core/base/status.h"
#include "core/tin/tin.h"
#include "core/tin/triangle_batch.h"
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
  // The id the next triangle row written gets: 1 + the largest in the table.
  Result<int64_t> NextTriangleId();
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

 private:
  std::string Where() const;  // "surface 'name'"

  Connection& db_;
  const SurfaceInfo& surface_;
};

}  // namespace tinbase
