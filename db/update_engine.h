// UpdateEngine: applies one local edit of a surface's constraints (new draped polylines of new
// features, the constraints of removed features) by re-triangulating only the conflict region
// (DESIGN.md, "Inserting a polygon", steps 3-5).
//
// The conflict region R is found by walking the stored neighbour links: the triangles each new
// segment touches (from its located first vertex), the stars of the vertices whose constraints
// go, grown by every triangle across an unconstrained edge whose circumcircle holds a new point.
// A new segment whose ends snap onto the ends of a stored constraint runs along it and seeds
// nothing: constraining an edge that already is one leaves the CDT as it is, so it only gains an
// owner (a map's shared boundaries: half the segments of a layer loaded feature by feature).
// R alone is re-triangulated in CGAL (core/geometry/cdt) with its outline constrained (only to
// keep the patch's boundary; never persisted), the old constraints inside it and the new ones,
// then refined from the DEM to the surface tolerance (core/tin/tolerance_refiner). When an
// outline edge is then not locally Delaunay (or a refinement point split it), the triangle across
// joins R and R is re-triangulated again, so the result is the constrained Delaunay
// triangulation of the stored vertices and constraints. Triangles outside R keep their ids and
// rows except the neighbour links that cross R's outline; visibility and tags of the triangles
// around the changed features are recomputed (db/feature_store PaintFromFeatures) and updated
// where they differ: triangle by triangle near a ring or nodata, and a whole centroid block at
// a time, unread, where no ring comes near (core/tin/ring_blocks); replace features set the z
// of the vertices they cover.
//
// An edit whose seeded R holds more than half of the surface's triangles (a whole map in one
// transaction) takes R to be the whole surface instead: every row is read in one scan, the
// surface is re-triangulated and refined once (no outline to settle), the new triangle rows are
// inserted 64 to a statement and the old ones deleted by one statement. Vertices that stay keep
// their ids; every triangle gets a new one.
//
// Ownership: borrows the Store; all writes happen inside the caller's WriteTransaction, so an
// error (or the fault hook) leaves the rollback to it. An edit that writes ~1e5 rows (a fill
// over most of a surface) raises the connection's page cache (db/sqlite/scoped_page_cache.h)
// until the engine is destroyed: destroy it after the commit. Not thread-safe; one edit at a
// time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/tin/tin.h"
#include "db/dem_store.h"
#include "db/feature_store.h"
#include "db/mesh_cache.h"
#include "db/sqlite/scoped_page_cache.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

// A draped polyline of a feature: its vertices become constraint vertices (kind kRing unless
// they land on an existing vertex), its segments constraints owned by `feature`.
struct EditPolyline {
  std::vector<TinVertex> points;
  bool closed = false;
  int64_t feature = 0;
};

// A new point closer than kSnapCells DEM cells to an existing vertex (of the triangle holding it)
// or to an earlier point of the same edit is moved onto it, and an existing vertex that close to
// a new segment (not its ends) becomes a point of the segment. A new point that close to a kept
// constrained edge (away from its ends and off the domain boundary) is moved onto it, and the
// edge is split there for every feature that owns it.
inline constexpr double kSnapCells = 1e-3;

// An edit whose seeded conflict region holds more than half of the surface's triangles
// re-triangulates the whole surface at once and rewrites its triangle rows in bulk (every
// triangle then gets a new id; vertices that stay keep theirs). Regions smaller than this many
// triangles never take that path, so a small edit never counts the surface's rows (an index
// scan, ~0.1 us a triangle: ~0.1 s for 1e6, against the edit's ~15 us a region triangle).
inline constexpr size_t kMinWholeSurfaceRegion = 4096;

struct LocalEdit {
  std::vector<EditPolyline> add;
  // Features whose constraints go: the engine deletes their constraint rows; their feature rows
  // must still exist during Apply (a removed replace feature's polygons say which vertices get
  // their DEM z back) and are the caller's to delete afterwards.
  std::vector<int64_t> remove;
  // The surface's features as they are after the edit, in id order: what paint, replace levels
  // and the tolerance exceptions are computed from.
  std::vector<EditorFeature> features;
  // Geometry of the added and removed features: where paint or replace levels may change.
  Box changed;
  // The new points of every edit of the load this one belongs to, when the caller applies a
  // load edit by edit with one MeshCache (`polygon add --each`) that can keep the whole surface
  // (at most half MeshCache::kMaxKeptTriangles); else 0, as for an edit on its own.
  size_t load_points = 0;
};

struct EditResult {
  int64_t removed = 0;        // triangles deleted (the conflict region)
  int64_t added = 0;          // triangles inserted
  int64_t visible_added = 0;  // of those, visible
  int64_t repainted = 0;      // existing triangles outside R whose visibility or tag changed
  int64_t refinement_points = 0;
  int rounds = 0;  // re-triangulations of R until its outline was Delaunay
  Box region;      // bbox of R
  // R was the whole surface (kMinWholeSurfaceRegion).
  bool whole_surface = false;
  // Every row of the surface was read in one scan (MeshCache::LoadSurface) before the edit.
  bool read_whole_surface = false;
};

// Called before each write step (numbered 1, 2, ... within one Apply); a non-OK Status aborts
// the edit with that Status. The atomicity tests inject failures with it. The polygon editor
// also calls it with step 0 before each edit's transaction begins (a test writes from another
// connection there).
using FaultHook = std::function<Status(int step)>;

class UpdateEngine {
 public:
  // REQUIRES: `surface` has a DEM (`dem`); both outlive the engine.
  UpdateEngine(Store& store, const SurfaceInfo& surface, DemStore& dems, const DemInfo& dem);
  ~UpdateEngine();

  void set_fault_hook(FaultHook hook) { fault_hook_ = std::move(hook); }
  // Reads the stored rows through `cache` (db/mesh_cache.h) instead of a cache of its own for
  // each Apply, and forgets there every row it writes. The caller keeps the cache current: Begin
  // before Apply, Committed after the commit, Clear after any failure.
  void set_mesh_cache(MeshCache* cache) { mesh_cache_ = cache; }

  // Applies `edit`. InvalidArgument naming the feature and point when a new point lies outside
  // the surface; Corruption when stored rows are inconsistent; the hook's Status when it fails.
  // REQUIRES: inside a WriteTransaction; the features of edit.add already have their rows.
  Result<EditResult> Apply(const LocalEdit& edit);

 private:
  Store& store_;
  const SurfaceInfo& surface_;
  DemStore& dems_;
  const DemInfo& dem_;
  FaultHook fault_hook_;
  MeshCache* mesh_cache_ = nullptr;
  std::unique_ptr<ScopedPageCache> page_cache_;
};

}  // namespace tinbase
