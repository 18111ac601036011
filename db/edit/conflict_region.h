// The first stage of an edit (db/edit/update_engine.h): find the conflict region R, the stored
// triangles the edit re-triangulates (docs/design.md, "Inserting a polygon", step 3).
//
// R is found by walking the stored neighbour links: the triangles each new segment touches (from
// its located first vertex), the stars of the vertices whose constraints go, the inside of
// removed replace features, grown by every triangle across an unconstrained edge whose
// circumcircle holds a new point. A new segment whose ends snap onto the ends of a stored
// constraint runs along it and seeds nothing: constraining an edge that already is one leaves
// the CDT as it is, so it only gains an owner (a map's shared boundaries: half the segments of a
// layer loaded feature by feature). A region that holds more than half of the surface's
// triangles becomes the whole surface (kMinWholeSurfaceRegion).
//
// Reads through the mesh cache and the point locator only; writes nothing. Not thread-safe.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <unordered_set>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/polygon_locator.h"
#include "db/edit/edit_context.h"
#include "db/edit/local_edit.h"
#include "db/mesh/mesh_edge.h"

namespace tinbase {

struct ConflictRegion {
  std::vector<int64_t> triangles;       // R, in the order found
  std::unordered_set<int64_t> members;  // R
  // Constrained edges all of whose owners the edit removes.
  std::set<MeshEdge> removed_edges;
  // Ring or Steiner vertices of removed constraints left on no constraint: they go.
  std::set<int64_t> dropped;
  // Kept constraints that new points snapped onto: (position along min -> max id, point).
  std::map<MeshEdge, std::vector<std::pair<double, Point2>>> splits;
  // Kept constrained edges that new segments run along: the features they gain as owners.
  std::map<MeshEdge, std::vector<int64_t>> present;
  // The new polylines as they enter the re-triangulation: snapped, without the segments along
  // kept constraints, with the existing vertices they pass through as points.
  std::vector<EditPolyline> lines;
  std::vector<EditorFeature> removed_features;    // rows of edit.remove, as stored
  std::shared_ptr<const PolygonLocator> restore;  // removed replace features' inside, or null
  bool whole_surface = false;                     // R is every triangle of the surface
  bool read_whole_surface = false;  // every row was read in one scan (MeshCache::LoadSurface)

  void Add(int64_t t) {
    if (members.insert(t).second) triangles.push_back(t);
  }
  bool Has(int64_t t) const { return members.count(t) > 0; }
};

// R for `edit` on the surface as stored. InvalidArgument naming the feature and point when a
// new point lies outside the surface; Corruption when stored rows are inconsistent.
// REQUIRES: the rows of edit.remove's features still exist.
Result<ConflictRegion> FindConflictRegion(const EditContext& ctx, const LocalEdit& edit);

// The triangles across R's failed outline edges join R with two rings of their neighbours: the
// outline then moves three triangles out, where the new triangulation seldom reaches, so R
// settles in fewer rounds (each re-triangulates all of R). Corruption when a row is missing.
Status GrowAround(MeshCache& mesh, const std::vector<int64_t>& failed, ConflictRegion* region);

}  // namespace tinbase
