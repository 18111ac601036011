// MeshCache: the stored mesh rows of one surface that local edits and point location read
// (triangles with their links and paint, vertices, constraint owners), loaded on demand by id and
// kept in memory. It reads the rows through MeshTables (db/mesh/mesh_tables.h) and holds them as
// TriangleRow and VertexRow (db/mesh/mesh_rows.h).
//
// Within one edit every read happens before the first write, so the rows stay current. A load
// feature by feature (`polygon add --each`) keeps one cache across its transactions: the engine
// applies every MeshDelta it writes (Apply: the rows written are put, the deleted forgotten), so
// after a commit the cache holds only rows as stored, and the next edit starts from them instead of
// reading them again. That is valid only while nobody else wrote in between: Begin() drops
// everything unless the store's change number is the one after Committed()'s and no other
// connection has committed since (SQLite's data_version), and when it has grown past
// kMaxKeptTriangles. After a failed or rolled-back edit the caller must Clear() (an edit may have
// forgotten only part of what it wrote, or read rows it had itself written).
//
// Ownership: borrows the Store and SurfaceInfo, which must outlive it. Not thread-safe.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/base/paged_id_map.h"
#include "core/base/status.h"
#include "core/geometry/predicates.h"
#include "core/tin/tin.h"
#include "db/feature_store.h"
#include "db/mesh/mesh_rows.h"
#include "db/mesh/mesh_tables.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

struct MeshDelta;  // db/edit/mesh_delta.h

class MeshCache {
 public:
  using Edge = std::pair<int64_t, int64_t>;  // (min, max) store vertex ids

  // Bounds the memory rows kept across transactions take (~150 bytes a triangle with its share
  // of vertices and owners). Kept rows pay because edits write through (Put*): with rows only
  // forgotten on write, the rows the next edit needed were the ones just forgotten.
  static constexpr size_t kMaxKeptTriangles = 1000000;
  // And the memory their pages take: rows of edits spread over a large surface fill few slots of
  // each page (core/base/paged_id_map.h).
  static constexpr size_t kMaxKeptBytes = size_t{256} << 20;

  MeshCache(Store& store, const SurfaceInfo& surface)
      : store_(store), surface_(surface), tables_(store.db(), surface) {}
  MeshCache(const MeshCache&) = delete;
  MeshCache& operator=(const MeshCache&) = delete;

  // Starts an edit that will become change `tx`: keeps the rows when the last commit this cache
  // saw was change tx - 1, no other connection has committed since and at most
  // kMaxKeptTriangles triangles in at most kMaxKeptBytes are held, else drops them. Kept rows
  // are completed with every constraint row of the surface when there are at most
  // kMaxKeptTriangles of those.
  // REQUIRES: inside the edit's WriteTransaction. Returns whether the rows were kept; an error
  // only when the store cannot be read (the rows are then dropped).
  Result<bool> Begin(int64_t tx);
  // The edit that Begin() started committed as change `tx`, every row it wrote forgotten.
  // REQUIRES: called right after the commit of the transaction Begin() was called in.
  void Committed(int64_t tx);
  // Drops every row (after a failure or rollback).
  void Clear();

  // Rows by id. Corruption naming the surface when the row is missing.
  Result<const TriangleRow*> Triangle(int64_t id);
  Result<const TinVertex*> Vertex(int64_t id);
  Result<Point2> At(int64_t vertex);
  // Whether triangle `id` exists (from memory when it is cached).
  Result<bool> HasTriangle(int64_t id);

  // The features owning constrained edge (a, b), 0 for a row without feature; empty when the
  // edge is not constrained.
  Result<const std::vector<int64_t>*> Owners(int64_t a, int64_t b);
  // Every constrained edge of `feature` (read from the store, not kept).
  Result<std::vector<Edge>> EdgesOf(int64_t feature);

  // The triangles whose centroid block meets `box` (through the block index); their rows are
  // cached on the way.
  Result<std::vector<int64_t>> TrianglesInBox(const Box& box);
  // Appends the triangles whose centroid block is one of (bx0..bx1, by) to `ids`, in id order
  // per block. Once read, a block's members are kept (with every row of them) and follow the
  // edits' writes, so the next edit of a load finds them without a query.
  Status TrianglesInBlocks(int64_t by, int64_t bx0, int64_t bx1, std::vector<int64_t>* ids);

  // Reads blocks `packed` (BlockGrid::Pack ids, sorted) whole, a run of consecutive blocks of a
  // row in one range of the block index, and then the vertices of their triangles
  // (ReadVerticesOf): an edit reads the blocks along its new rings in a few statements instead
  // of one lookup per row as its walks reach them (a lookup costs several times a row of a
  // range).
  Status ReadBlocks(const std::vector<int64_t>& packed);
  // Reads the vertices of triangles `ids` (cached) that are not cached yet, in ranges of ids:
  // the surface writers give neighbouring vertices neighbouring ids (MeshTables::InsertVertices),
  // so the ids of a patch fall in runs. The constraint rows starting at a vertex of a range are
  // read with them, so Owners() answers the edges from those vertices (nearly all unconstrained)
  // without a lookup each.
  Status ReadVerticesOf(const std::vector<int64_t>& ids);
  // Rows between two wanted ids less than kGap apart are read with them (a lookup by id costs
  // several times the next row of a range).
  static constexpr int64_t kGap = 16;

  // Reads every triangle, vertex and constraint row of the surface in one scan each (rows
  // already held are kept: they are as stored), so that an edit over most of the surface looks
  // nothing up row by row; Owners() then answers from memory until an edge is forgotten, and
  // TrianglesInBlocks() for every block. Returns the surface's triangle ids in id order.
  Result<std::vector<int64_t>> LoadSurface();
  // Whether every triangle and vertex row of the surface is held (LoadSurface, then kept through
  // the edits' writes); false again once the rows are dropped.
  bool holds_whole_surface() const { return whole_surface_; }

  // The triangles around `vertex`, starting from `start` (one of them), counter-clockwise;
  // `closed` is false when the vertex lies on the domain boundary.
  Result<std::vector<int64_t>> Star(int64_t vertex, int64_t start, bool* closed);

  // Whether Owners() answers every edge from memory (an edge it lacks is unconstrained).
  bool knows_every_constraint() const { return owners_complete_; }

  // Applies an edit's MeshDelta (written to the store in this transaction) to the rows held, in
  // the order the writer wrote them: new rows are put, deleted ones forgotten, relinked and
  // repainted ones updated. The only way rows held change (Clear and Begin only drop them).
  void Apply(const MeshDelta& delta);

  // Tests: reads every cached row again from the store; Corruption naming the first row that
  // differs from (or is missing in) the store.
  Status VerifyAgainstStore();

 private:
  // ---- The writes Apply is made of.

  // A row the current edit deletes, or writes without telling its content: read again from the
  // store when next asked for.
  void ForgetTriangle(int64_t id);
  void ForgetVertex(int64_t id) { vertices_.Erase(id); }
  // A row the current edit writes, as written (write-through): the next edit of a load feature by
  // feature reads the rows the last one wrote more than any other, so they are kept, not
  // forgotten.
  void PutTriangle(int64_t id, const TriangleRow& t);
  void PutVertex(int64_t id, const TinVertex& v) { vertices_.Put(id, v); }
  // Triangle `id`'s paint is now this (a no-op when it is not cached).
  void Repaint(int64_t id, bool visible, const std::optional<int64_t>& tag);
  // `feature` now owns constrained edge (a, b) too (one row more).
  void AddOwner(int64_t a, int64_t b, int64_t feature);
  // Edge (a, b) has no constraint row now.
  void SetUnconstrained(int64_t a, int64_t b);
  void ForgetAllOwners();
  // Every row (an edit rewrote the whole surface); unlike Clear() the rows of the next edit may
  // still be kept (Begin).
  void ForgetAllRows();

  struct EdgeHash {
    size_t operator()(const Edge& e) const {
      return std::hash<int64_t>()(e.first) * 1000003u ^ std::hash<int64_t>()(e.second);
    }
  };

  // Every constraint row of the surface into owners_ (complete).
  Status LoadOwners();
  // Whether every constraint row whose smaller vertex is `va` is in owners_.
  bool KnowsOwnersOf(int64_t va) const;
  // Reads the constraint rows whose smaller vertex lies in [first, last] into owners_.
  Status ReadOwnersOf(int64_t first, int64_t last);
  // The same when the surface has at most kMaxKeptTriangles constraint rows: an edit asks for the
  // owners of every edge of its region, nearly all of them unconstrained, and a load feature by
  // feature whose rows are kept would otherwise look each new one up.
  Status LoadOwnersIfFew();
  // The surface's constraint rows in the store.
  Result<int64_t> StoredConstraintRows();
  Result<int64_t> DataVersion();

  Store& store_;
  const SurfaceInfo& surface_;
  MeshTables tables_;  // every row read goes through it
  PagedIdMap<TriangleRow> triangles_;
  // Blocks whose every triangle is in triangles_: their ids, ascending.
  std::unordered_map<int64_t, std::vector<int64_t>> block_members_;
  PagedIdMap<TinVertex> vertices_;
  std::unordered_map<Edge, std::vector<int64_t>, EdgeHash> owners_;
  // owners_ holds every constrained edge of the surface (LoadSurface): an edge it lacks is not
  // constrained. False once any edge is forgotten.
  bool owners_complete_ = false;
  // Vertex id ranges whose constraint rows (by smaller vertex) are all in owners_, sorted by
  // first id: an edge from such a vertex that owners_ lacks is unconstrained.
  std::vector<std::pair<int64_t, int64_t>> owner_ranges_;
  static constexpr size_t kMaxOwnerRanges = size_t{1} << 16;
  bool whole_surface_ = false;  // holds_whole_surface()
  // The last commit: its change number and the connection's data_version in its transaction
  // (unchanged by the connection's own commit); -1 when the rows are not known to be current
  // beyond the edit in progress.
  int64_t committed_tx_ = -1;
  int64_t data_version_ = -1;
  int64_t pending_version_ = -1;  // read by Begin() in the edit's transaction
};

}  // namespace tinbase
