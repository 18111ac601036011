#include "db/edit/mesh_delta_writer.h"

#include <algorithm>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "db/sql/bulk_write.h"
#include "db/sql/unchecked_foreign_keys.h"

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

// Binds (surface, v0, v1, v2, n0, n1, n2, visible, tag, block) of `t` from parameter p on.
void BindTriangleRow(Statement& row, int p, int64_t surface, const TriangleRow& t) {
  row.Bind(p, surface);
  for (int i = 0; i < 3; ++i) {
    row.Bind(p + 1 + i, t.v[i]);
    if (t.n[i])
      row.Bind(p + 4 + i, *t.n[i]);
    else
      row.BindNull(p + 4 + i);
  }
  row.Bind(p + 7, int64_t{t.visible ? 1 : 0});
  if (t.tag)
    row.Bind(p + 8, *t.tag);
  else
    row.BindNull(p + 8);
  row.Bind(p + 9, t.block);
}

void BindPaint(Statement& stmt, bool visible, const std::optional<int64_t>& tag) {
  stmt.Bind(1, int64_t{visible ? 1 : 0});
  if (tag)
    stmt.Bind(2, *tag);
  else
    stmt.BindNull(2);
}

// Steps 1 and 2: the new vertices, numbered on from first_vertex, and the changed z of the
// region's vertices.
Status WriteVertices(Connection& db, const MeshDelta& delta, const WriteStepHook& step) {
  TB_RETURN_IF_ERROR(step(1));
  TB_RETURN_IF_ERROR(InsertNumberedRows(db, "vertices(surface, x, y, z, kind)", 5,
                                        delta.new_vertices.size(), delta.first_vertex,
                                        [&](Statement& row, int p, size_t k) {
                                          const TinVertex& v = delta.new_vertices[k];
                                          row.Bind(p, delta.surface).Bind(p + 1, v.x);
                                          row.Bind(p + 2, v.y).Bind(p + 3, v.z);
                                          row.BindStaticText(p + 4, VertexKindName(v.kind));
                                        }));
  TB_RETURN_IF_ERROR(step(2));
  TB_ASSIGN_OR_RETURN(Statement * set_z, db.Cached("UPDATE vertices SET z = ? WHERE id = ?"));
  for (const VertexZ& v : delta.region_z)
    TB_RETURN_IF_ERROR(set_z->Bind(1, v.vertex.z).Bind(2, v.id).Run());
  return Status::Ok();
}

// Step 3: the new triangles get ids above every id in the table, so an id never comes back with
// another triangle: they are inserted before the region's rows go, SQLite numbering them on from
// the largest id (InsertNumberedRows).
Status WriteNewTriangles(Connection& db, const MeshDelta& delta, const WriteStepHook& step) {
  TB_RETURN_IF_ERROR(step(3));
  // Every key bound here holds: the surface is the one being edited, the tags were interned by
  // the builder in this transaction.
  TB_ASSIGN_OR_RETURN(auto unchecked, UncheckedIf(db, delta.whole_surface));
  return InsertNumberedRows(db, "triangles(surface, v0, v1, v2, n0, n1, n2, visible, tag, block)",
                            10, delta.new_triangles.size(), delta.first_triangle,
                            [&](Statement& row, int p, size_t k) {
                              BindTriangleRow(row, p, delta.surface, delta.new_triangles[k]);
                            });
}

// Step 4: the region's rows go: the whole surface's in one statement, a local region's in one
// statement per run of consecutive ids (its triangles were mostly written together, in block
// order, so a run is often dozens of rows; an IN list of the ids of short runs cost more:
// SQLite builds a temporary table of them for each statement). Then the dropped vertices.
Status DeleteRegion(Connection& db, const MeshDelta& delta, const WriteStepHook& step) {
  TB_RETURN_IF_ERROR(step(4));
  if (delta.whole_surface) {
    TB_ASSIGN_OR_RETURN(Statement * del_all,
                        db.Cached("DELETE FROM triangles WHERE surface = ? AND id < ?"));
    TB_RETURN_IF_ERROR(del_all->Bind(1, delta.surface).Bind(2, delta.first_triangle).Run());
    if (db.Changes() != static_cast<int64_t>(delta.deleted_triangles.size()))
      return Status::Corruption("surface '" + delta.surface_name + "': " +
                                std::to_string(db.Changes()) + " triangle rows instead of " +
                                std::to_string(delta.deleted_triangles.size()) + " were replaced");
  } else {
    std::vector<int64_t> ids = delta.deleted_triangles;
    std::sort(ids.begin(), ids.end());
    TB_ASSIGN_OR_RETURN(Statement * del,
                        db.Cached("DELETE FROM triangles WHERE id BETWEEN ? AND ?"));
    for (size_t first = 0; first < ids.size();) {
      size_t last = first;
      while (last + 1 < ids.size() && ids[last + 1] == ids[last] + 1) ++last;
      TB_RETURN_IF_ERROR(del->Bind(1, ids[first]).Bind(2, ids[last]).Run());
      first = last + 1;
    }
  }
  TB_ASSIGN_OR_RETURN(Statement * del_vertex, db.Cached("DELETE FROM vertices WHERE id = ?"));
  for (int64_t v : delta.deleted_vertices) TB_RETURN_IF_ERROR(del_vertex->Bind(1, v).Run());
  return Status::Ok();
}

// Step 5: the triangles outside the region point across its outline at the new ones. One
// UPDATE a row: cheaper than batches, whether REPLACE of whole rows or UPDATE ... FROM a VALUES
// list.
Status WriteRelinks(Connection& db, const MeshDelta& delta, const WriteStepHook& step) {
  TB_RETURN_IF_ERROR(step(5));
  TB_ASSIGN_OR_RETURN(Statement * relink,
                      db.Cached("UPDATE triangles SET n0 = ?, n1 = ?, n2 = ? WHERE id = ?"));
  for (const auto& [id, t] : delta.relinked) {
    for (int i = 0; i < 3; ++i) {
      if (t.n[i])
        relink->Bind(1 + i, *t.n[i]);
      else
        relink->BindNull(1 + i);
    }
    TB_RETURN_IF_ERROR(relink->Bind(4, id).Run());
  }
  return Status::Ok();
}

// Step 6: constraint rows. The new ones go in the order of the (surface, va, vb) index, so that
// its entries go in one sweep; every key holds (the surface is this one, each feature an added
// one, written before the edit, or an owner of a kept constraint).
Status WriteConstraints(Connection& db, const MeshDelta& delta, const WriteStepHook& step) {
  TB_RETURN_IF_ERROR(step(6));
  TB_ASSIGN_OR_RETURN(Statement * del_feature,
                      db.Cached("DELETE FROM constraints WHERE surface = ? AND feature = ?"));
  for (int64_t f : delta.removed_features)
    TB_RETURN_IF_ERROR(del_feature->Bind(1, delta.surface).Bind(2, f).Run());
  TB_ASSIGN_OR_RETURN(Statement * del_edge,
                      db.Cached("DELETE FROM constraints WHERE surface = ? AND va = ? AND vb = ?"));
  for (const MeshEdge& e : delta.split_constraints)
    TB_RETURN_IF_ERROR(del_edge->Bind(1, delta.surface).Bind(2, e.first).Bind(3, e.second).Run());
  TB_ASSIGN_OR_RETURN(auto unchecked, UncheckedIf(db, delta.whole_surface));
  return InsertRows(db, "constraints(surface, va, vb, feature)", 4, delta.added_constraints.size(),
                    [&](Statement& row, int p, size_t c) {
                      const auto& [e, feature] = delta.added_constraints[c];
                      row.Bind(p, delta.surface).Bind(p + 1, e.first);
                      row.Bind(p + 2, e.second);
                      if (feature != 0)
                        row.Bind(p + 3, feature);
                      else
                        row.BindNull(p + 3);
                    });
}

// The rows `ids` take one paint, up to 64 ids a statement.
Status RepaintByIds(Connection& db, bool visible, const std::optional<int64_t>& tag,
                    const std::vector<int64_t>& ids, int64_t* repainted) {
  return RunOverIds(
      db, "UPDATE triangles SET visible = ?1, tag = ?2 WHERE id IN",
      " AND (visible IS NOT ?1 OR tag IS NOT ?2)", 2, ids,
      [&](Statement& stmt) { BindPaint(stmt, visible, tag); }, repainted);
}

// Long runs of consecutive ids that take the same paint are one UPDATE each: the builders store
// a surface's triangles in block order, so a filled polygon's inside is a few long runs, and a
// run walks the table in id order, faster than looking every row up. The rest (around a ring
// runs are short: two rows on average in a map loaded feature by feature) are looked up by id,
// up to 64 of one paint in one statement (an UPDATE costs several times a row's lookup). Rows
// that already have the paint are not rewritten, and only the rows that change count.
// REQUIRES: `repaints` ascending by triangle.
Status WriteRepaints(Connection& db, const std::vector<TriangleRepaint>& repaints,
                     int64_t* repainted) {
  TB_ASSIGN_OR_RETURN(Statement * repaint_run,
                      db.Cached("UPDATE triangles SET visible = ?1, tag = ?2 WHERE "
                                "id BETWEEN ?3 AND ?4 AND "
                                "(visible IS NOT ?1 OR tag IS NOT ?2)"));
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
    BindPaint(*repaint_run, paint.visible, paint.tag);
    TB_RETURN_IF_ERROR(repaint_run->Bind(3, paint.triangle).Bind(4, repaints[last].triangle).Run());
    *repainted += db.Changes();
    first = last + 1;
  }
  for (const auto& [paint, ids] : by_paint)
    TB_RETURN_IF_ERROR(RepaintByIds(db, paint.first, paint.second, ids, repainted));
  return Status::Ok();
}

// Step 7: paint around the changed features and of uniform blocks, then z around.
Status WritePaint(Connection& db, const MeshDelta& delta, const WriteStepHook& step,
                  int64_t* repainted) {
  TB_RETURN_IF_ERROR(step(7));
  TB_RETURN_IF_ERROR(WriteRepaints(db, delta.repaints, repainted));
  TB_RETURN_IF_ERROR(WriteRepaints(db, delta.block_repaints, repainted));
  TB_ASSIGN_OR_RETURN(Statement * set_z, db.Cached("UPDATE vertices SET z = ? WHERE id = ?"));
  for (const VertexZ& v : delta.around_z)
    TB_RETURN_IF_ERROR(set_z->Bind(1, v.vertex.z).Bind(2, v.id).Run());
  return Status::Ok();
}

}  // namespace

Result<int64_t> WriteMeshDelta(Connection& db, const MeshDelta& delta, const WriteStepHook& step) {
  TB_RETURN_IF_ERROR(WriteVertices(db, delta, step));
  TB_RETURN_IF_ERROR(WriteNewTriangles(db, delta, step));
  TB_RETURN_IF_ERROR(DeleteRegion(db, delta, step));
  TB_RETURN_IF_ERROR(WriteRelinks(db, delta, step));
  TB_RETURN_IF_ERROR(WriteConstraints(db, delta, step));
  int64_t repainted = 0;
  TB_RETURN_IF_ERROR(WritePaint(db, delta, step, &repainted));
  return repainted;
}

}  // namespace tinbase
