#include "db/edit/update_engine.h"

#include <algorithm>
#include <utility>

#include "db/edit/conflict_region.h"
#include "db/edit/edit_context.h"
#include "db/edit/elevation_rules.h"
#include "db/edit/local_patch.h"
#include "db/edit/mesh_delta.h"
#include "db/edit/mesh_delta_builder.h"
#include "db/edit/mesh_delta_writer.h"
#include "db/edit/region_lock.h"
#include "db/edit/repaint_plan.h"
#include "db/edit/update_engine_test_hooks.h"

namespace tinbase {
namespace {

// The rows the write deletes, inserts and repaints (a uniform block holds about the builders'
// number), which the connection's page cache is raised to hold.
size_t RowsWritten(const ConflictRegion& region, const LocalPatch& patch, const RepaintPlan& plan) {
  const auto inserted =
      static_cast<size_t>(std::count(patch.inside.begin(), patch.inside.end(), uint8_t{1}));
  return region.triangles.size() + inserted + plan.around.size() +
         plan.uniform_blocks.size() * BlockGrid::kDefaultPerBlock;
}

EditResult Summarize(const ConflictRegion& region, const LocalPatch& patch, const MeshDelta& delta,
                     int64_t repainted) {
  EditResult result;
  result.removed = static_cast<int64_t>(delta.deleted_triangles.size());
  result.added = static_cast<int64_t>(delta.new_triangles.size());
  for (const TriangleRow& t : delta.new_triangles) result.visible_added += t.visible;
  result.repainted = repainted;
  result.refinement_points = patch.refinement_points;
  result.rounds = patch.rounds;
  result.region = patch.region;
  result.whole_surface = region.whole_surface;
  result.read_whole_surface = region.read_whole_surface;
  return result;
}

}  // namespace

UpdateEngine::UpdateEngine(Store& store, const SurfaceInfo& surface, DemStore& dems,
                           const DemInfo& dem)
    : store_(store), surface_(surface), dems_(dems), dem_(dem) {}

UpdateEngine::~UpdateEngine() = default;

Result<EditResult> UpdateEngine::Apply(const LocalEdit& edit) {
  std::unique_ptr<MeshCache> own;
  MeshCache* mesh = mesh_cache_;
  if (!mesh) {
    own = std::make_unique<MeshCache>(store_, surface_);
    mesh = own.get();
  }
  const EditContext ctx{store_, surface_, dems_, dem_, *mesh};

  // 1. The conflict region R (seeded by the new segments and the removed constraints).
  TB_ASSIGN_OR_RETURN(ConflictRegion region, FindConflictRegion(ctx, edit));
  // 2. Where paint may change: planned first, the patch's DEM window covers it.
  RepaintPlan plan;
  if (region.whole_surface) {
    plan = WholeSurfaceRepaintPlan(edit);
  } else {
    TB_ASSIGN_OR_RETURN(plan, PlanRepaint(ctx, edit, region.removed_features));
  }
  // 3. R re-triangulated and refined until its outline is locally Delaunay (R may grow).
  ElevationRules rules(dems_, dem_, edit.features, region.restore);
  rules.set_resample(edit.resample);
  TB_ASSIGN_OR_RETURN(LocalPatch patch,
                      RetriangulateUntilSettled(ctx, rules, plan.paint_box, edit.remove, &region));
  TB_RETURN_IF_ERROR(rules.status());
  // With concurrent writers: the region's blocks locked before anything is written.
  Box locked = patch.region;
  locked.Add(plan.paint_box);
  TB_RETURN_IF_ERROR(LockEditRegion(store_.db(), surface_.id, surface_.blocks, locked,
                                    plan.uniform_blocks, region.whole_surface));
  TEST_RegionLocked();
  // 4. Everything the edit changes, as one value; the last read of the edit.
  if (!page_cache_ || !page_cache_->raised())
    page_cache_ = std::make_unique<LargeWriteHint>(store_.db(), RowsWritten(region, patch, plan));
  TB_ASSIGN_OR_RETURN(const MeshDelta delta, BuildMeshDelta(ctx, rules, edit, region, patch, plan));
  TB_RETURN_IF_ERROR(rules.status());
  // 5. The one writer, then the cache from the same delta.
  TB_ASSIGN_OR_RETURN(const int64_t repainted,
                      WriteMeshDelta(store_.db(), surface_, delta, TEST_FaultStep, mesh_image_));
  mesh->Apply(delta);
  return Summarize(region, patch, delta, repainted);
}

}  // namespace tinbase
