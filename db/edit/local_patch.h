// The second stage of an edit (db/edit/update_engine.h): re-triangulate the conflict region R
// and refine it until its outline is locally Delaunay (docs/design.md, "Inserting a polygon",
// step 4). The result is a local patch: a Tin of R's new triangles and how its vertices map to the
// store.
//
// R alone is re-triangulated in CGAL (core/geometry/cdt) with its outline constrained (only to
// keep the patch's boundary; never persisted), the old constraints inside it and the new ones,
// then refined from the DEM to the surface tolerance (core/tin/tolerance_refiner). When an
// outline edge is then not locally Delaunay (or a refinement point split it), the triangle across
// joins R (GrowAround) and R is re-triangulated again, so the result is the constrained Delaunay
// triangulation of the stored vertices and constraints.
//
// Reads through the mesh cache and the DEM store; writes nothing. Not thread-safe.
#pragma once

#include <cstdint>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "core/raster/grid.h"
#include "core/tin/tin.h"
#include "db/edit/conflict_region.h"
#include "db/edit/edit_context.h"
#include "db/edit/elevation_rules.h"
#include "db/mesh/mesh_edge.h"

namespace tinbase {

// An outline edge of R: the directed edge a->b of a triangle of R, and the stored triangle across
// it (none on the domain boundary).
struct OutlineEdge {
  int64_t a = 0, b = 0;
  std::optional<int64_t> outer;
};

struct LocalPatch {
  Tin tin;                                      // local CDT; its constraints include R's outline
  std::vector<uint8_t> inside;                  // per local triangle: part of R
  std::vector<int64_t> store_ids;               // per local vertex: store id, 0 for a new vertex
  std::unordered_map<int64_t, uint32_t> local;  // store id -> local index
  std::vector<std::vector<uint32_t>> lines;     // local index of each point of region.lines
  // Kept constrained edges of R, each once, with their owners after the edit.
  std::vector<std::pair<MeshEdge, std::vector<int64_t>>> old_constraints;
  std::vector<OutlineEdge> outline;  // R's outline
  Grid grid;                         // the DEM under R and the paint box, with a margin
  Box region;                        // bbox of R
  int64_t refinement_points = 0;
  int rounds = 0;  // re-triangulations of R until its outline was Delaunay
};

// The patch of R once its outline is locally Delaunay, growing `region` as needed.
// `paint_box`: where the paint may change (the DEM window covers it too). Corruption when R does
// not settle within 200 rounds or stored rows are inconsistent; DEM read errors.
Result<LocalPatch> RetriangulateUntilSettled(const EditContext& ctx, const ElevationRules& rules,
                                             const Box& paint_box,
                                             const std::vector<int64_t>& remove,
                                             ConflictRegion* region);

}  // namespace tinbase
