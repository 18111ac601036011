#include "db/history/mesh_image_store.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "db/sql/bulk_write.h"

namespace tinbase {

namespace {

// Runs of consecutive ids in `ids` (ascending, unique): one range statement each, as the edit's
// rows were mostly written together in id order.
template <typename Map>
std::vector<std::pair<int64_t, int64_t>> IdRuns(const Map& ids) {
  std::vector<std::pair<int64_t, int64_t>> runs;
  for (const auto& entry : ids) {
    const int64_t id = entry.first;
    if (!runs.empty() && runs.back().second + 1 == id) {
      runs.back().second = id;
    } else {
      runs.emplace_back(id, id);
    }
  }
  return runs;
}

std::optional<int64_t> OptionalColumn(const Statement& s, int column) {
  if (s.ColumnIsNull(column)) return std::nullopt;
  return s.ColumnInt(column);
}

Status ReadTriangles(Connection& db, MeshRowSet* rows) {
  TB_ASSIGN_OR_RETURN(Statement * s,
                      db.Cached("SELECT id, v0, v1, v2, n0, n1, n2, visible, tag, block "
                                "FROM triangles WHERE id >= ? AND id <= ?"));
  for (auto& [id, row] : rows->triangles) row.reset();
  for (const auto& [first, last] : IdRuns(rows->triangles)) {
    s->Bind(1, first).Bind(2, last);
    while (true) {
      TB_ASSIGN_OR_RETURN(const bool more, s->Step());
      if (!more) break;
      TriangleRow t;
      for (int k = 0; k < 3; ++k) t.v[k] = s->ColumnInt(1 + k);
      for (int k = 0; k < 3; ++k) t.n[k] = OptionalColumn(*s, 4 + k);
      t.visible = s->ColumnInt(7) != 0;
      t.tag = OptionalColumn(*s, 8);
      t.block = s->ColumnInt(9);
      rows->triangles[s->ColumnInt(0)] = t;
    }
    s->Reset();
  }
  return Status::Ok();
}

Status ReadVertices(Connection& db, MeshRowSet* rows) {
  TB_ASSIGN_OR_RETURN(Statement * s, db.Cached("SELECT id, x, y, z, kind FROM vertices "
                                               "WHERE id >= ? AND id <= ?"));
  for (auto& [id, row] : rows->vertices) row.reset();
  for (const auto& [first, last] : IdRuns(rows->vertices)) {
    s->Bind(1, first).Bind(2, last);
    while (true) {
      TB_ASSIGN_OR_RETURN(const bool more, s->Step());
      if (!more) break;
      VertexRow v;
      v.x = s->ColumnDouble(1);
      v.y = s->ColumnDouble(2);
      v.z = s->ColumnDouble(3);
      const int64_t id = s->ColumnInt(0);
      if (!ParseVertexKind(s->ColumnText(4), &v.kind)) {
        s->Reset();
        return Status::Corruption("vertex " + std::to_string(id) + ": unknown kind");
      }
      rows->vertices[id] = v;
    }
    s->Reset();
  }
  return Status::Ok();
}

Status ReadConstraints(Connection& db, int64_t surface, MeshRowSet* rows) {
  TB_ASSIGN_OR_RETURN(Statement * s, db.Cached("SELECT feature, kind FROM constraints "
                                               "WHERE surface = ? AND va = ? AND vb = ?"));
  for (auto& [edge, list] : rows->constraints) {
    list.clear();
    s->Bind(1, surface).Bind(2, edge.first).Bind(3, edge.second);
    while (true) {
      TB_ASSIGN_OR_RETURN(const bool more, s->Step());
      if (!more) break;
      list.push_back({OptionalColumn(*s, 0), s->ColumnText(1) == "soft"});
    }
    s->Reset();
    std::sort(list.begin(), list.end());
  }
  return Status::Ok();
}

// The edges of the surface's constraint rows owned by `feature`.
Status AddEdgesOfFeature(Connection& db, int64_t surface, int64_t feature, MeshRowSet* keys) {
  TB_ASSIGN_OR_RETURN(Statement * s, db.Cached("SELECT va, vb FROM constraints "
                                               "WHERE surface = ? AND feature = ?"));
  s->Bind(1, surface).Bind(2, feature);
  while (true) {
    TB_ASSIGN_OR_RETURN(const bool more, s->Step());
    if (!more) break;
    keys->constraints[{s->ColumnInt(0), s->ColumnInt(1)}];
  }
  s->Reset();
  return Status::Ok();
}

void BindOptional(Statement& s, int index, const std::optional<int64_t>& v) {
  if (v) {
    s.Bind(index, *v);
  } else {
    s.BindNull(index);
  }
}

Status WriteTriangles(Connection& db, int64_t surface, const MeshRowSet& rows) {
  TB_ASSIGN_OR_RETURN(Statement * erase,
                      db.Cached("DELETE FROM triangles WHERE id >= ? AND id <= ?"));
  for (const auto& [first, last] : IdRuns(rows.triangles))
    TB_RETURN_IF_ERROR(erase->Bind(1, first).Bind(2, last).Run());
  std::vector<std::pair<int64_t, const TriangleRow*>> present;
  for (const auto& [id, t] : rows.triangles)
    if (t) present.emplace_back(id, &*t);
  return InsertRows(db, "triangles(id, surface, v0, v1, v2, n0, n1, n2, visible, tag, block)", 11,
                    present.size(), [&](Statement& row, int p, size_t k) {
                      const auto& [id, t] = present[k];
                      row.Bind(p, id).Bind(p + 1, surface);
                      for (int c = 0; c < 3; ++c) row.Bind(p + 2 + c, t->v[c]);
                      for (int c = 0; c < 3; ++c) BindOptional(row, p + 5 + c, t->n[c]);
                      row.Bind(p + 8, static_cast<int64_t>(t->visible ? 1 : 0));
                      BindOptional(row, p + 9, t->tag);
                      row.Bind(p + 10, t->block);
                    });
}

Status WriteVertices(Connection& db, int64_t surface, const MeshRowSet& rows) {
  TB_ASSIGN_OR_RETURN(Statement * erase,
                      db.Cached("DELETE FROM vertices WHERE id >= ? AND id <= ?"));
  for (const auto& [first, last] : IdRuns(rows.vertices))
    TB_RETURN_IF_ERROR(erase->Bind(1, first).Bind(2, last).Run());
  std::vector<std::pair<int64_t, const VertexRow*>> present;
  for (const auto& [id, v] : rows.vertices)
    if (v) present.emplace_back(id, &*v);
  return InsertRows(db, "vertices(id, surface, x, y, z, kind)", 6, present.size(),
                    [&](Statement& row, int p, size_t k) {
                      const auto& [id, v] = present[k];
                      row.Bind(p, id).Bind(p + 1, surface).Bind(p + 2, v->x).Bind(p + 3, v->y);
                      row.Bind(p + 4, v->z).BindStaticText(p + 5, VertexKindName(v->kind));
                    });
}

Status WriteConstraints(Connection& db, int64_t surface, const MeshRowSet& rows) {
  TB_ASSIGN_OR_RETURN(Statement * erase, db.Cached("DELETE FROM constraints WHERE surface = ? "
                                                   "AND va = ? AND vb = ?"));
  TB_ASSIGN_OR_RETURN(Statement * insert, db.Cached("INSERT INTO constraints(surface, va, vb, "
                                                    "feature, kind) VALUES (?, ?, ?, ?, ?)"));
  for (const auto& [edge, list] : rows.constraints) {
    TB_RETURN_IF_ERROR(erase->Bind(1, surface).Bind(2, edge.first).Bind(3, edge.second).Run());
    for (const EdgeConstraint& c : list) {
      insert->Bind(1, surface).Bind(2, edge.first).Bind(3, edge.second);
      BindOptional(*insert, 4, c.feature);
      TB_RETURN_IF_ERROR(insert->BindStaticText(5, c.soft ? "soft" : "hard").Run());
    }
  }
  return Status::Ok();
}

// The keys `delta` writes, without their rows.
Result<MeshRowSet> KeysOf(Connection& db, const MeshDelta& delta) {
  MeshRowSet keys;
  const auto add_triangle = [&](int64_t id) { keys.triangles[id]; };
  for (int64_t id : delta.deleted_triangles) add_triangle(id);
  for (size_t k = 0; k < delta.new_triangles.size(); ++k)
    add_triangle(delta.first_triangle + static_cast<int64_t>(k));
  for (const auto& [id, row] : delta.relinked) add_triangle(id);
  for (const TriangleRepaint& r : delta.repaints) add_triangle(r.triangle);
  for (const TriangleRepaint& r : delta.block_repaints) add_triangle(r.triangle);
  for (int64_t id : delta.deleted_vertices) keys.vertices[id];
  for (size_t k = 0; k < delta.new_vertices.size(); ++k)
    keys.vertices[delta.first_vertex + static_cast<int64_t>(k)];
  for (const VertexZ& v : delta.region_z) keys.vertices[v.id];
  for (const VertexZ& v : delta.around_z) keys.vertices[v.id];
  for (int64_t f : delta.removed_features)
    TB_RETURN_IF_ERROR(AddEdgesOfFeature(db, delta.surface, f, &keys));
  for (const MeshEdge& e : delta.split_constraints) keys.constraints[e];
  for (const auto& [e, feature] : delta.added_constraints) keys.constraints[e];
  return keys;
}

}  // namespace

Status ReadMeshRows(Connection& db, int64_t surface, MeshRowSet* rows) {
  TB_RETURN_IF_ERROR(ReadTriangles(db, rows));
  TB_RETURN_IF_ERROR(ReadVertices(db, rows));
  return ReadConstraints(db, surface, rows);
}

Status WriteMeshRows(Connection& db, int64_t surface, const MeshRowSet& rows) {
  TB_RETURN_IF_ERROR(WriteVertices(db, surface, rows));
  TB_RETURN_IF_ERROR(WriteTriangles(db, surface, rows));
  return WriteConstraints(db, surface, rows);
}

Status CaptureMeshBefore(Connection& db, const MeshDelta& delta, MeshImage* image) {
  image->surface = delta.surface;
  TB_ASSIGN_OR_RETURN(MeshRowSet keys, KeysOf(db, delta));
  // Keys an earlier edit of the transaction captured keep the row from before it.
  std::erase_if(keys.triangles,
                [&](const auto& e) { return image->before.triangles.count(e.first); });
  std::erase_if(keys.vertices,
                [&](const auto& e) { return image->before.vertices.count(e.first); });
  std::erase_if(keys.constraints,
                [&](const auto& e) { return image->before.constraints.count(e.first); });
  TB_RETURN_IF_ERROR(ReadMeshRows(db, delta.surface, &keys));
  image->before.AddMissing(keys);
  return Status::Ok();
}

Status RecordMeshImage(Store& store, int64_t tx, MeshImage image) {
  MeshRowSet after = image.before;
  TB_RETURN_IF_ERROR(ReadMeshRows(store.db(), image.surface, &after));
  image.after_digest = Digest(after);
  return StoreMeshImage(store, tx, image);
}

Status StoreMeshImage(Store& store, int64_t tx, const MeshImage& image) {
  const std::vector<uint8_t> bytes = EncodeMeshImage(image);
  TB_ASSIGN_OR_RETURN(Statement * s, store.db().Cached("INSERT INTO mesh_images(tx, surface, "
                                                       "image) VALUES (?, ?, ?)"));
  return s->Bind(1, tx).Bind(2, image.surface).BindBlob(3, bytes.data(), bytes.size()).Run();
}

Result<std::optional<MeshImage>> LoadMeshImage(Store& store, int64_t tx) {
  TB_ASSIGN_OR_RETURN(Statement * s,
                      store.db().Cached("SELECT image FROM mesh_images WHERE tx = ?"));
  s->Bind(1, tx);
  TB_ASSIGN_OR_RETURN(const bool found, s->Step());
  if (!found) {
    s->Reset();
    return std::optional<MeshImage>();
  }
  size_t size = 0;
  const uint8_t* data = s->ColumnBlob(0, &size);
  auto image = DecodeMeshImage(data, size, "mesh image of transaction " + std::to_string(tx));
  s->Reset();
  if (!image.ok()) return image.status();
  return std::optional<MeshImage>(std::move(*image));
}

}  // namespace tinbase
