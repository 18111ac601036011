// The input and the result of one local edit of a surface's constraints (db/edit/update_engine.h),
// and the thresholds that shape it. Plain data.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/tin/tin.h"
#include "db/feature_store.h"

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
// scan over the surface, which costs more than a small edit's whole region).
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
  // Stored triangles that join R whatever the new polylines reach, and boxes whose existing
  // vertices take the DEM's z again (unless a replace level covers them): a resurvey
  // (db/edit/resurvey.h) re-triangulates where the DEM changed. Every vertex in `resample` must
  // have its whole star among `seed`, so that R's outline keeps its z.
  std::vector<int64_t> seed;
  std::vector<Box> resample;
  // Stored vertices that go with the edit although no constraint of theirs does: the survey
  // points of a removed `points` feature (db/edit/mass_points.h). Their stars join R. A vertex
  // still on a kept constraint (a later ring snapped onto it) stays.
  std::vector<int64_t> drop_vertices;
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

}  // namespace tinbase
