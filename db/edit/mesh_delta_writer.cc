#include "db/edit/mesh_delta_writer.h"

#include <cassert>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "db/edit/constraint_kinds.h"
#include "db/history/mesh_image_store.h"
#include "db/mesh/mesh_tables.h"
#include "db/sql/unchecked_foreign_keys.h"
#include "db/surface_store.h"

namespace tinbase {
namespace {

// Consecutive ids from which one statement over their range beats looking each up by id.
constexpr size_t kLongRun = 8;

// Foreign keys unchecked (db/sql/unchecked_foreign_keys.h) while the result lives, for the
// bulk statements of a whole-surface edit, whose keys the builder has made sure of. A local
// edit keeps them checked: turning enforcement off and on again expires every prepared
// statement of the connection, and with them unchecked in every edit a
// load feature by feature (`--each`) took more CPU than before instead of less.
Result<std::optional<UncheckedForeignKeys>> UncheckedIf(Connection& db, bool whole_surface) {
  if (!whole_surface) return std::optional<UncheckedForeignKeys>();
  TB_ASSIGN_OR_RETURN(UncheckedForeignKeys unchecked, UncheckedForeignKeys::Begin(db));
  return std::optional<UncheckedForeignKeys>(std::move(unchecked));
}

// Steps 1 and 2: the new vertices, numbered on from first_vertex, and the changed z of the
// region's vertices.
Status WriteVertices(MeshTables& tables, const MeshDelta& delta, const WriteStepHook& step) {
  TB_RETURN_IF_ERROR(step(1));
  TB_RETURN_IF_ERROR(tables.AppendVertices(delta.first_vertex, delta.new_vertices));
  TB_RETURN_IF_ERROR(step(2));
  return tables.SetVertexZ(delta.region_z);
}

// Step 3: the new triangles get ids above every id in the table, so an id never comes back with
// another triangle: they are inserted before the region's rows go, SQLite numbering them on from
// the largest id (InsertNumberedRows).
Status WriteNewTriangles(Connection& db, MeshTables& tables, const MeshDelta& delta,
                         const WriteStepHook& step) {
  TB_RETURN_IF_ERROR(step(3));
  // Every key bound here holds: the surface is the one being edited, the tags were interned by
  // the builder in this transaction.
  TB_ASSIGN_OR_RETURN(auto unchecked, UncheckedIf(db, delta.whole_surface));
  return tables.AppendTriangles(delta.first_triangle, delta.new_triangles);
}

// Step 4: the region's rows go: the whole surface's in one statement, a local region's in one
// statement per run of consecutive ids (MeshTables::DeleteTriangles). Then the dropped vertices.
Status DeleteRegion(MeshTables& tables, const MeshDelta& delta, const WriteStepHook& step) {
  TB_RETURN_IF_ERROR(step(4));
  if (delta.whole_surface) {
    TB_ASSIGN_OR_RETURN(const int64_t deleted, tables.DeleteTrianglesBelow(delta.first_triangle));
    if (deleted != static_cast<int64_t>(delta.deleted_triangles.size()))
      return Status::Corruption("surface '" + delta.surface_name + "': " + std::to_string(deleted) +
                                " triangle rows instead of " +
                                std::to_string(delta.deleted_triangles.size()) + " were replaced");
  } else {
    TB_RETURN_IF_ERROR(tables.DeleteTriangles(delta.deleted_triangles));
  }
  return tables.DeleteVertices(delta.deleted_vertices);
}

// Step 5: the triangles outside the region point across its outline at the new ones.
Status WriteRelinks(MeshTables& tables, const MeshDelta& delta, const WriteStepHook& step) {
  TB_RETURN_IF_ERROR(step(5));
  return tables.Relink(delta.relinked);
}

// Step 6: constraint rows. The new ones go in the order of the (surface, va, vb) index, so that
// its entries go in one sweep; every key holds (the surface is this one, each feature an added
// one, written before the edit, or an owner of a kept constraint).
Status WriteConstraints(Connection& db, MeshTables& tables, const MeshDelta& delta,
                        const WriteStepHook& step) {
  TB_RETURN_IF_ERROR(step(6));
  TB_RETURN_IF_ERROR(tables.DeleteConstraintsOfFeatures(delta.removed_features));
  TB_RETURN_IF_ERROR(tables.DeleteConstraints(delta.split_constraints));
  TB_ASSIGN_OR_RETURN(auto unchecked, UncheckedIf(db, delta.whole_surface));
  TB_RETURN_IF_ERROR(tables.InsertConstraints(delta.added_constraints));
  return MarkSoftConstraints(db, delta.surface, delta.added_constraints);
}

// Long runs of consecutive ids that take the same paint are one UPDATE each: the builders store
// a surface's triangles in block order, so a filled polygon's inside is a few long runs, and a
// run walks the table in id order, faster than looking every row up. The rest (around a ring
// runs are short: two rows on average in a map loaded feature by feature) are looked up by id,
// up to 64 of one paint in one statement (an UPDATE costs several times a row's lookup). Rows
// that already have the paint are not rewritten, and only the rows that change count.
// REQUIRES: `repaints` ascending by triangle.
Status WriteRepaints(MeshTables& tables, const std::vector<TriangleRepaint>& repaints,
                     int64_t* repainted) {
  std::map<std::pair<bool, std::optional<int64_t>>, std::vector<int64_t>> by_paint;
  for (size_t first = 0; first < repaints.size();) {
    const TriangleRepaint& paint = repaints[first];
    size_t last = first;
    while (last + 1 < repaints.size() &&
           repaints[last + 1].triangle == repaints[last].triangle + 1 &&
           repaints[last + 1].visible == paint.visible && repaints[last + 1].tag == paint.tag)
      ++last;
    if (last + 1 - first < kLongRun) {
      std::vector<int64_t>& ids = by_paint[{paint.visible, paint.tag}];
      for (size_t k = first; k <= last; ++k) ids.push_back(repaints[k].triangle);
      first = last + 1;
      continue;
    }
    TB_ASSIGN_OR_RETURN(
        const int64_t changed,
        tables.RepaintRange(paint.triangle, repaints[last].triangle, paint.visible, paint.tag));
    *repainted += changed;
    first = last + 1;
  }
  for (const auto& [paint, ids] : by_paint) {
    TB_ASSIGN_OR_RETURN(const int64_t changed, tables.RepaintIds(paint.first, paint.second, ids));
    *repainted += changed;
  }
  return Status::Ok();
}

// Step 7: paint around the changed features and of uniform blocks, then z around.
Status WritePaint(MeshTables& tables, const MeshDelta& delta, const WriteStepHook& step,
                  int64_t* repainted) {
  TB_RETURN_IF_ERROR(step(7));
  TB_RETURN_IF_ERROR(WriteRepaints(tables, delta.repaints, repainted));
  TB_RETURN_IF_ERROR(WriteRepaints(tables, delta.block_repaints, repainted));
  return tables.SetVertexZ(delta.around_z);
}

}  // namespace

Result<int64_t> WriteMeshDelta(Connection& db, const SurfaceInfo& surface, const MeshDelta& delta,
                               const WriteStepHook& step, MeshImage* image) {
  assert(delta.surface == surface.id);
  if (image != nullptr) TB_RETURN_IF_ERROR(CaptureMeshBefore(db, delta, image));
  MeshTables tables(db, surface);
  TB_RETURN_IF_ERROR(WriteVertices(tables, delta, step));
  TB_RETURN_IF_ERROR(WriteNewTriangles(db, tables, delta, step));
  TB_RETURN_IF_ERROR(DeleteRegion(tables, delta, step));
  TB_RETURN_IF_ERROR(WriteRelinks(tables, delta, step));
  TB_RETURN_IF_ERROR(WriteConstraints(db, tables, delta, step));
  int64_t repainted = 0;
  TB_RETURN_IF_ERROR(WritePaint(tables, delta, step, &repainted));
  return repainted;
}

}  // namespace tinbase
