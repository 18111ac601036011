// SurfaceStore: the `surfaces` table, and whole surfaces read and written as the topological
// tables of docs/format.md (vertices, triangles with neighbour links, tags, constraints), whose
// rows it reads and writes through MeshTables (db/mesh/mesh_tables.h).
//
// Store ids are global row ids; a Tin's indices are positions. Writing assigns ids up front so
// neighbour links are written in one pass. Borrows the Store. Thread-safety: one SurfaceStore
// per Store.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/tin/block_grid.h"
#include "core/tin/tin.h"
#include "core/tin/triangle_batch.h"
#include "db/mesh/mesh_rows.h"
#include "db/store.h"

namespace tinbase {

enum class SurfaceKind { kDelaunay, kFree };
const char* SurfaceKindName(SurfaceKind kind);  // "delaunay" / "free"
// False when `name` is not one of the store spellings.
bool ParseSurfaceKind(const std::string& name, SurfaceKind* kind);

struct SurfaceInfo {
  int64_t id = 0;
  std::string name;
  SurfaceKind kind = SurfaceKind::kDelaunay;
  std::string method;               // "greedy", ...
  std::optional<double> tolerance;  // vertical tolerance in metres, when one was asked for
  std::optional<int64_t> dem;       // the DEM it is draped on
  BlockGrid blocks;                 // bucket grid of triangle centroids
};

struct SurfaceCounts {
  int64_t vertices = 0;
  int64_t triangles = 0;
  int64_t visible_triangles = 0;
  int64_t constraints = 0;
  int64_t features = 0;
};

// A surface loaded whole: the Tin plus the store id of every vertex and triangle.
struct LoadedSurface {
  Tin tin;
  std::vector<int64_t> vertex_ids;    // vertex_ids[i] is the store id of tin.vertices[i]
  std::vector<int64_t> triangle_ids;  // likewise for tin.triangles
};

// The block of the triangle (a, b, c): the grid cell of its centroid. Every writer of `triangles`
// uses this one formula, so the integrity check can recompute blocks bit for bit.
int64_t CentroidBlock(const BlockGrid& grid, double ax, double ay, double bx, double by, double cx,
                      double cy);

// A ReadSnapshot for a multi-query read, or null when the connection is already inside a
// transaction (a WriteTransaction's own view is then the consistent one, and SQLite cannot nest
// BEGIN). Fails only when starting the snapshot fails.
Result<std::unique_ptr<ReadSnapshot>> SnapshotUnlessInTransaction(Store& store);

class SurfaceStore {
 public:
  explicit SurfaceStore(Store& store) : store_(store) {}

  // Writes `tin` as a new surface named spec.name (Conflict if the name is taken), computing
  // the block grid and each triangle's block; returns spec with its id and block grid filled in.
  // InvalidArgument when `tin` refers to a vertex, neighbour or tag it does not have, or a
  // coordinate is not finite. REQUIRES: inside a WriteTransaction; `tin`'s neighbour links are
  // consistent (LinkNeighbours).
  Result<SurfaceInfo> Create(const SurfaceInfo& spec, const Tin& tin);
  // Triangulates, handing the triangles over in batches sorted by `order` as they become final
  // (TriangleBatch); returns its own errors. Runs as a TBB task, beside the writing thread.
  using BatchedTriangulation =
      std::function<Status(const TriangleOrder& order, const TriangleSink& finished)>;
  // As Create, for a bulk import whose triangles are still to be computed from `vertices`:
  // `triangulate` runs as a TBB task while this thread writes the surface and vertex rows, and
  // then each batch's triangle rows as it comes (neighbours not final yet are written NULL and
  // filled in when a later batch links them). The block grid is sized for 2n triangles before
  // the count is known. Errors: Create's, and those `triangulate` returns; InvalidArgument when a
  // batch's indices do not fit `vertices` and the triangles before it. REQUIRES: inside a
  // WriteTransaction; `triangulate` touches no store, and indexes `vertices` in order.
  Result<SurfaceInfo> CreateWhileTriangulating(const SurfaceInfo& spec,
                                               const std::vector<TinVertex>& vertices,
                                               const BatchedTriangulation& triangulate);
  // Replaces every vertex, triangle and constraint row of `surface` by `tin` (features and
  // changes stay). The surface keeps its block grid (blocks clamp at the grid's edge, so a larger
  // `tin` stays correct, only coarser to search). Returns the new ids. InvalidArgument when
  // `tin` refers to a vertex, neighbour or tag it does not have or a coordinate is not finite.
  // REQUIRES: inside a WriteTransaction; `tin`'s neighbour links are consistent.
  Result<LoadedSurface> Replace(const SurfaceInfo& surface, const Tin& tin);

  // Every surface, by name.
  Result<std::vector<SurfaceInfo>> List();
  // NotFound "no surface named 'x'" when absent.
  Result<SurfaceInfo> Find(const std::string& name);
  // NotFound "no surface with id n" when absent.
  Result<SurfaceInfo> FindById(int64_t id);
  Result<SurfaceCounts> Count(const SurfaceInfo& surface);

  // The row of triangle (vertex) `id`; NotFound naming the row and surface when `id` is not a
  // triangle (vertex) of `surface` (MeshTables::Triangle, MeshTables::Vertex).
  Result<TriangleRow> Triangle(const SurfaceInfo& surface, int64_t id);
  Result<VertexRow> Vertex(const SurfaceInfo& surface, int64_t id);
  // The value of tag id `tag` (TriangleRow::tag); NotFound when the tags table has no such row.
  Result<std::string> TagValue(const SurfaceInfo& surface, int64_t tag);
  // Some triangle whose block is `block`, if any (the "jump" of jump-and-walk).
  Result<std::optional<int64_t>> AnyTriangleInBlock(const SurfaceInfo& surface, int64_t block);
  // Some triangle of the surface; NotFound when it has none.
  Result<int64_t> AnyTriangle(const SurfaceInfo& surface);

  // The whole surface in memory, vertices and triangles in id order. Corruption when a triangle
  // or constraint refers to a vertex or triangle the surface does not have (CheckStore says
  // more).
  Result<LoadedSurface> Load(const SurfaceInfo& surface);

 private:
  // Writes `tin`'s rows for `surface` with fresh ids; returns the ids (and an empty Tin).
  Result<LoadedSurface> WriteRows(const SurfaceInfo& surface, const Tin& tin);
  Result<SurfaceInfo> FindWhere(const char* where, const std::function<void(Statement&)>& bind,
                                const std::string& absent);

  Store& store_;
};

}  // namespace tinbase
