// UpdateEngine: applies one local edit of a surface's constraints (new draped polylines of new
// features, the constraints of removed features) by re-triangulating only the conflict region R
// (docs/design.md, "Inserting a polygon", steps 3-5). Triangles outside R keep their ids and rows
// except the neighbour links that cross R's outline; visibility and tags of the triangles around
// the changed features are recomputed and updated where they differ; replace features set the z
// of the vertices they cover.
//
// An edit is a pipeline of stages that return values (db/edit/):
//   1. conflict_region: find R                                  -> ConflictRegion
//   2. repaint_plan: where paint may change                     -> RepaintPlan
//   3. local_patch: re-triangulate R until its outline settles  -> LocalPatch
//   4. mesh_delta_builder: everything the edit changes          -> MeshDelta
//   5. mesh_delta_writer: the one writer of the mesh rows; then the mesh cache applies the same
//      MeshDelta (MeshCache::Apply).
// Between 3 and 4, with concurrent writers (PostgreSQL), the edit locks its region's blocks
// (db/edit/region_lock.h).
// Every read happens before the first write. An edit whose seeded R holds more than half of the
// surface's triangles takes R to be the whole surface instead (kMinWholeSurfaceRegion): every
// row is read in one scan, the surface is re-triangulated and refined once, the new rows are
// inserted in bulk and the old ones deleted by one statement. Vertices that stay keep their ids;
// every triangle gets a new one. Tests reach the edit through db/edit/update_engine_test_hooks.h.
//
// Ownership: borrows the Store; all writes happen inside the caller's WriteTransaction, so an
// error leaves the rollback to it. An edit that writes many rows (a fill over most of a surface)
// raises the connection's page cache (db/sql/large_write_hint.h) until the engine is
// destroyed: destroy it after the commit. Not thread-safe; one edit at a time.
#pragma once

#include <memory>

#include "core/base/status.h"
#include "db/dem_store.h"
#include "db/edit/local_edit.h"
#include "db/mesh_cache.h"
#include "db/sql/large_write_hint.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

struct MeshImage;  // db/history/mesh_image.h

class UpdateEngine {
 public:
  // REQUIRES: `surface` has a DEM (`dem`); both outlive the engine.
  UpdateEngine(Store& store, const SurfaceInfo& surface, DemStore& dems, const DemInfo& dem);
  ~UpdateEngine();

  // Reads the stored rows through `cache` (db/mesh_cache.h) instead of a cache of its own for
  // each Apply, and applies there every change it writes. The caller keeps the cache current:
  // Begin before Apply, Committed after the commit, Clear after any failure.
  void set_mesh_cache(MeshCache* cache) { mesh_cache_ = cache; }

  // Adds the before-image of every row an Apply changes to `image` (db/history/mesh_image.h),
  // which the caller stores with its transaction (RecordMeshImage) for an exact revert.
  void set_mesh_image(MeshImage* image) { mesh_image_ = image; }

  // Applies `edit`. InvalidArgument naming the feature and point when a new point lies outside
  // the surface; Corruption when stored rows are inconsistent.
  // REQUIRES: inside a WriteTransaction; the features of edit.add already have their rows.
  Result<EditResult> Apply(const LocalEdit& edit);

 private:
  Store& store_;
  const SurfaceInfo& surface_;
  DemStore& dems_;
  const DemInfo& dem_;
  MeshCache* mesh_cache_ = nullptr;
  std::unique_ptr<LargeWriteHint> page_cache_;
  MeshImage* mesh_image_ = nullptr;
};

}  // namespace tinbase
