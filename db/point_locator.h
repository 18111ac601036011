// PointLocator: which stored triangle holds a point, and the surface's z there.
//
// Jump-and-walk over the stored neighbour links (docs/design.md, "Point location"): jump to a
// triangle whose centroid block is the point's (or the nearest non-empty block around it), then
// walk across the edge the point lies beyond, choosing among candidate edges at random
// (Devillers' remembering stochastic walk) so the walk terminates on non-Delaunay surfaces too.
// Reads O(walk length) rows through MeshTables (db/mesh/mesh_tables.h), never the whole surface,
// all in one read snapshot. PointLocator locates many points in a row, each walk starting where
// the last one ended when the point is near the last one (within two blocks): points along a
// ring or sorted in space are then a few steps apart instead of a jump and a walk each, and a
// point far away jumps instead of walking across the surface. Thread-safety: one per Store.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "core/geometry/predicates.h"
#include "db/mesh_cache.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

struct Location {
  int64_t triangle = 0;
  double z = 0;  // linear interpolation in the triangle (barycentric)
  bool visible = true;
  std::optional<std::string> tag;
  int steps = 0;  // triangles visited by the walk
};

// The triangle holding (x, y) (a point on an edge or a vertex is held by any of the triangles
// around it), with z interpolated there. NotFound "point (x, y) is outside surface 'name'" when
// no triangle holds it; Corruption when the rows the walk reads are inconsistent (CheckStore
// tells which). Works inside a WriteTransaction too (then reads what it has written).
Result<Location> LocatePoint(Store& store, const SurfaceInfo& surface, double x, double y);

// z at (x, y) of the plane through the triangle p[0..2] with heights z[0..2], by barycentric
// interpolation relative to p[0] (so large map coordinates do not cancel away the small
// differences that matter): the z every Location reports.
double PlaneZ(const std::array<Point2, 3>& p, const std::array<double, 3>& z, double x, double y);

// LocatePoint for a sequence of points of one surface. It remembers the rows it read (the last
// triangle and the vertices), so the surface must not change while it is in use: hold a
// ReadSnapshot or a WriteTransaction around the calls (and make a new locator after writing), or
// answers may mix the states before and after another writer's commit.
//
// With a MeshCache (db/mesh_cache.h), the walk reads its rows through it: the update engine shares
// its cache with the locator, so the rows a walk reads are not read again by the edit (nor by the
// next edit of a load feature by feature).
class PointLocator {
 public:
  // REQUIRES: `cache`, when given, is of `surface` and outlives the locator.
  PointLocator(Store& store, const SurfaceInfo& surface, MeshCache* cache = nullptr);
  ~PointLocator();
  PointLocator(const PointLocator&) = delete;
  PointLocator& operator=(const PointLocator&) = delete;

  // As LocatePoint.
  Result<Location> Locate(double x, double y);
  // As Locate, without reading the triangle's visibility and tag (left at their defaults).
  Result<Location> LocateTriangle(double x, double y);

 private:
  class Walker;
  std::unique_ptr<Walker> walker_;
};

}  // namespace tinbase
