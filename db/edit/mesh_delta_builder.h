// The last stage before the write (db/edit/update_engine.h): turns the settled patch of R, the
// region and the repaint plan into the MeshDelta of the edit (db/edit/mesh_delta.h): ids for the
// new vertices and triangles (on from the tables' largest), the new triangles' links and paint,
// the stored triangles relinked across R's outline, the constraint rows that go and come, the
// repaints and z changes around.
//
// Reads through the mesh cache (every row it needs is as stored: nothing is written before the
// delta is complete) and interns the tags the new paint uses (tags table). Not thread-safe.
#pragma once

#include "core/base/status.h"
#include "db/edit/conflict_region.h"
#include "db/edit/edit_context.h"
#include "db/edit/elevation_rules.h"
#include "db/edit/local_edit.h"
#include "db/edit/local_patch.h"
#include "db/edit/mesh_delta.h"
#include "db/edit/repaint_plan.h"

namespace tinbase {

// The delta of `edit`. Corruption, before anything is written, when the patch is inconsistent
// with R (a new vertex outside it, an outline edge lost, a constraint rerouted or lost by CGAL);
// InvalidArgument when a new vertex has no elevation; errors of the store.
Result<MeshDelta> BuildMeshDelta(const EditContext& ctx, const ElevationRules& rules,
                                 const LocalEdit& edit, const ConflictRegion& region,
                                 const LocalPatch& patch, const RepaintPlan& plan);

}  // namespace tinbase
