// IntegrityCheck: verifies the invariants a store promises (docs/design.md, "Invariants": 1-5, 8
// and that every tag exists; with the `full` option also 6 and 7), as PRAGMA integrity_check does
// for SQLite. Each broken invariant is a coded Problem naming the surface and triangle, in a
// stable order (by surface, then triangle id), so the first one is what `tinbase check` reports.
// It reads the rows through MeshTables (db/mesh/mesh_tables.h). Thread-safety: reads through one
// Store.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "db/store.h"

namespace tinbase {

// Problem codes, by invariant (stable: scripts and tests match on them):
//   1  vertex-missing        a triangle names a vertex that is not in its surface
//      clockwise-triangle    vertices turn clockwise (exact orientation)
//      degenerate-triangle   vertices are collinear (exact orientation)
//      duplicate-vertex      two vertices of a surface share x, y (no triangle)
//   2  bad-neighbour         a neighbour id is not a triangle of the surface
//      neighbour-edge-mismatch  the named neighbour does not have the edge reversed
//      asymmetric-neighbour  the neighbour has the edge but does not name this triangle back
//      missing-neighbour     an edge shared with another triangle has no neighbour
//      overused-edge         an edge is used twice in one direction (or by 3+ triangles)
//   3  euler                 V - E + F != 2C - B, or a vertex used by no triangle (no triangle)
//      overlap               the fan around a vertex turns more than once (on its lowest triangle)
//   4  constraint-not-edge   a constrained edge is not an edge (no triangle; hard and soft
//                            constraints alike: a softline is an edge for the surface's shape)
//      constraint-kind       a constraint row's kind is not 'soft' for a softline's row and
//                            'hard' for any other (no triangle)
//   5  not-delaunay          across an unconstrained edge the far vertex is strictly inside the
//                            circumcircle (`delaunay` surfaces only; on the lower triangle id)
//   6  unknown-tag           the tag is not an id of the tags table
//   8  wrong-block           the block column is not the block of the centroid
// With CheckOptions::full, on a surface whose structure (1-5, 8) is sound (9 on a surface with a
// DEM):
//   6  wrong-visibility      visible differs from the features' paint recomputed from scratch
//                            (db/feature_store PaintFromFeatures: modes in feature id order, and
//                            hidden where the centroid lies on DEM nodata)
//      wrong-tag             the tag differs from that paint
//   7  tolerance             a DEM cell centre covered by this visible triangle, outside every
//                            replace polygon, is further from the triangle's plane than the
//                            surface's tolerance (surfaces with a DEM and a tolerance; the
//                            message names the worst cell); cells within kLineBandCells of a 3D
//                            line (core/tin/line_elevation.h) are excepted too
//   9  line-z                a vertex of a 3D line's constraints (a line feature with z from the
//                            feature) does not have the z the 3D lines give it (no triangle)
// Problems without a triangle come first in their surface. A corruption usually shows up under
// several codes (a flipped triangle also breaks its links); the lowest triangle id comes first.
struct Problem {
  std::string code;  // one of the codes above
  int64_t surface = 0;
  std::optional<int64_t> triangle;
  std::string message;  // "surface 'terrain', triangle 412: vertices are clockwise"
};

struct CheckOptions {
  std::optional<std::string> surface;  // only this surface; default all
  bool full = false;                   // also invariants 6 and 7 (reads features and the DEM)
};

// The problems found (empty when the store is intact); a Status only when reading fails, or
// NotFound when options.surface names no surface. Reads each surface once, in one snapshot
// (or inside the caller's transaction); O(n log n) time and O(n) memory per surface.
Result<std::vector<Problem>> CheckStore(Store& store, const CheckOptions& options = {});

}  // namespace tinbase
