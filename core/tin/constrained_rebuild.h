// Constrained rebuild: a whole TIN re-triangulated with new constraint polylines (polygon rings,
// breaklines), the global form of polygon insertion used by the walking skeleton.
//
// The result is the constrained Delaunay triangulation (core/geometry/cdt) of all base vertices,
// the base constraints and the new polylines. Where constraints cross, a vertex of kind kSteiner
// is created with z from the caller's elevation function. The base triangles themselves are not
// consulted: only the base's vertices and constraints. Thread-safety: pure function.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/cdt.h"
#include "core/tin/tin.h"

namespace tinbase {

struct ConstraintPolyline {
  std::vector<TinVertex> points;  // their kind is ignored: new vertices are kRing
  bool closed = false;            // a ring: the last point joins the first
};

// Where the inputs went, as indices into the result's vertices.
struct ConstrainedRebuildMap {
  std::vector<uint32_t> base_vertices;               // by base vertex index
  std::vector<std::vector<uint32_t>> line_vertices;  // by line, then by point
};

// Returns a fresh Tin: the base vertices first (same order, so same indices when the base has
// no two vertices at one x, y), then the polylines' new vertices (kind kRing; a point at the x, y
// of an existing vertex maps to that vertex, which keeps its z and kind), then the crossing
// vertices (kSteiner). Tin::constraints lists every constrained sub-edge once: the base's and the
// new ones, split wherever a vertex lies on them or constraints cross. All triangles are visible
// and untagged (the caller recomputes both); Tin::tags is copied from the base.
// InvalidArgument, naming the line and point, for a polyline with fewer than 2 points (a closed
// one with fewer than 3 distinct points), non-finite coordinates, a base constraint naming a
// vertex that does not exist, a missing elevation function, or a crossing where it returns a
// non-finite z.
Result<Tin> InsertConstraints(const Tin& base, const std::vector<ConstraintPolyline>& lines,
                              const ElevationFn& elevation, ConstrainedRebuildMap* map = nullptr);

}  // namespace tinbase
