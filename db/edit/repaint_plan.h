// The repaint stage of an edit (db/edit/update_engine.h): where the visibility and tags of stored
// triangles may change, planned before R is re-triangulated (docs/design.md, "Inserting a
// polygon", step 5).
//
// Paint is a function of the features holding a triangle's centroid (and of nodata), so the plan
// goes block by block (centroid blocks, core/tin/ring_blocks.h) over the changed features' box: a
// block no changed ring comes near and whose centre no changed polygon holds keeps its paint and
// is skipped (a clip feature changes paint everywhere: skipping is off). A block no ring of any
// feature comes near, over DEM data only, takes one paint for all its triangles ("uniform"): it is
// repainted without its rows being read. The rest ("mixed" blocks) are read and painted triangle
// by triangle, as are all blocks when a changed feature sets vertex z (replace), since z is per
// vertex.
//
// Reads through the mesh cache, the DEM store and the block index. Not thread-safe.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_set>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/polygon_locator.h"
#include "core/tin/feature_paint.h"
#include "db/edit/edit_context.h"
#include "db/edit/local_edit.h"
#include "db/edit/mesh_delta.h"

namespace tinbase {

struct RepaintPlan {
  // Where paint may change: the changed features' box and the mixed blocks. The patch's DEM
  // window covers it (the paint of the triangles around reads the DEM at their centroids).
  Box paint_box;
  // The stored triangles of the mixed blocks (their rows are cached), to be painted one by one.
  std::vector<int64_t> around;
  // The added and removed features' inside; null when nothing is planned.
  std::shared_ptr<const PolygonLocator> changed_inside;
  // A stored triangle outside R lies wholly on one side of every changed ring, so one outside
  // changed_inside keeps its paint. Not so for clip (outside changes too) or replace (z changes
  // at the ring's vertices, found through the triangles).
  bool outside_keeps_paint = false;
  std::vector<int64_t> uniform_blocks;    // blocks repainted whole, in (by, bx) order
  Paint uniform_paint;                    // per uniform block
  std::vector<std::string> uniform_tags;  // what uniform_paint.tag indexes
};

// The plan for `edit` on a local conflict region. `removed_features`: the rows of edit.remove.
// DEM read errors; Corruption when stored rows are inconsistent.
Result<RepaintPlan> PlanRepaint(const EditContext& ctx, const LocalEdit& edit,
                                const std::vector<EditorFeature>& removed_features);

// The plan when R is the whole surface: no stored triangle is left to repaint (the paint of
// every new triangle is computed anyway).
RepaintPlan WholeSurfaceRepaintPlan(const LocalEdit& edit);

// The triangles of the uniform blocks as they are after the edit (the stored ones not in
// `deleted` (R), found through the block index without reading their rows, and the new ones of
// `delta` whose block is uniform), each with its block's paint, ascending by id. Interns the
// blocks' tags (a write to the tags table, in the caller's transaction). Errors of the store.
Result<std::vector<TriangleRepaint>> UniformBlockRepaints(
    const EditContext& ctx, const RepaintPlan& plan, const std::unordered_set<int64_t>& deleted,
    const MeshDelta& delta);

}  // namespace tinbase
