#include "db/edit/mesh_delta_builder.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/tin/block_grid.h"
#include "db/mesh/mesh_tables.h"

namespace tinbase {
namespace {

// The constrained sub-edges of the patch from local vertex a to b: a walk along constrained
// edges that advances along ab and stays on it (a crossing or a point on the segment splits it).
// Crossing points are constructed inexactly, so "on it" allows 1e-7 of its length; among the
// candidates the one nearest the line wins, so a crossing constraint is never followed.
Result<std::vector<std::pair<uint32_t, uint32_t>>> Pieces(
    const std::vector<std::vector<uint32_t>>& graph, const Tin& tin, uint32_t a, uint32_t b) {
  const TinVertex& pa = tin.vertices[a];
  const TinVertex& pb = tin.vertices[b];
  const double dx = pb.x - pa.x, dy = pb.y - pa.y, len2 = dx * dx + dy * dy;
  const double slack = 1e-7 * std::sqrt(len2);
  const auto along = [&](uint32_t w) {
    return ((tin.vertices[w].x - pa.x) * dx + (tin.vertices[w].y - pa.y) * dy) / len2;
  };
  const auto off = [&](uint32_t w) {
    return std::fabs((tin.vertices[w].x - pa.x) * dy - (tin.vertices[w].y - pa.y) * dx) /
           std::sqrt(len2);
  };
  std::vector<std::pair<uint32_t, uint32_t>> pieces;
  uint32_t at = a;
  for (size_t guard = 0; at != b; ++guard) {
    if (guard > tin.vertices.size()) break;
    uint32_t best = at;
    double best_off = slack;
    for (uint32_t w : graph[at]) {
      if (w == b) {
        best = b;
        break;
      }
      if (along(w) <= along(at) || along(w) >= 1) continue;
      if (const double d = off(w); d <= best_off) best_off = d, best = w;
    }
    if (best == at) break;
    pieces.emplace_back(at, best);
    at = best;
  }
  if (at != b)
    return Status::Corruption("the constraint " + FormatPoint({pa.x, pa.y}) + " - " +
                              FormatPoint({pb.x, pb.y}) +
                              " was lost while re-triangulating the conflict region");
  return pieces;
}

// The paint of the new triangles (first) and of the stored triangles around that may change.
struct Painting {
  Paint paint;
  std::vector<std::optional<int64_t>> tag_ids;  // by paint.tag index
  std::vector<int64_t> kept_around;             // the stored triangles painted, in paint order
  std::vector<int64_t> vertices;                // store ids of the painted triangles' vertices

  std::optional<int64_t> TagOf(size_t k) const {
    return paint.tag[k] == kNoTag ? std::optional<int64_t>() : tag_ids[paint.tag[k]];
  }
};

// Builds the delta: each method fills one part of it, in the order Run calls them.
class DeltaBuilder {
 public:
  DeltaBuilder(const EditContext& ctx, const ElevationRules& rules, const LocalEdit& edit,
               const ConflictRegion& region, const LocalPatch& patch, const RepaintPlan& plan)
      : ctx_(ctx),
        rules_(rules),
        edit_(edit),
        region_(region),
        patch_(patch),
        plan_(plan),
        tin_(patch.tin),
        ids_(patch.store_ids) {}

  Result<MeshDelta> Run() {
    delta_.surface = ctx_.surface.id;
    delta_.surface_name = ctx_.surface.name;
    delta_.whole_surface = region_.whole_surface;
    TB_RETURN_IF_ERROR(CheckNewVerticesInside());
    TB_RETURN_IF_ERROR(NumberVertices());
    TB_RETURN_IF_ERROR(NumberTriangles());
    TB_ASSIGN_OR_RETURN(const Painting painting, Paint());
    TriangleRows(painting);
    delta_.deleted_triangles = region_.triangles;
    delta_.deleted_vertices.assign(region_.dropped.begin(), region_.dropped.end());
    TB_RETURN_IF_ERROR(Relinks());
    TB_RETURN_IF_ERROR(Constraints());
    TB_RETURN_IF_ERROR(Repaints(painting));
    return std::move(delta_);
  }

 private:
  Status CheckNewVerticesInside() const;
  Status NumberVertices();
  Status NumberTriangles();
  Result<Painting> Paint() const;
  void TriangleRows(const Painting& painting);
  Status Relinks();
  Status Constraints();
  Status CheckNoConstraintRerouted(std::vector<MeshEdge> accounted) const;
  Status Repaints(const Painting& painting);

  const EditContext& ctx_;
  const ElevationRules& rules_;
  const LocalEdit& edit_;
  const ConflictRegion& region_;
  const LocalPatch& patch_;
  const RepaintPlan& plan_;
  const Tin& tin_;
  MeshDelta delta_;
  std::vector<int64_t> ids_;       // per local vertex: its store id, new ones included
  std::vector<uint32_t> written_;  // the inside triangles in row order
  std::vector<int64_t> new_id_;    // per local triangle: its store id (inside ones)
  std::vector<int64_t> block_;     // per local triangle: its centroid block (inside ones)
  MeshEdgeTable outer_across_;     // store (a, b) of R's side -> the triangle across
  std::vector<std::vector<uint32_t>> graph_;  // per local vertex: its constrained neighbours
};

// Every new vertex must be a corner of a triangle of R's patch.
Status DeltaBuilder::CheckNewVerticesInside() const {
  std::vector<uint8_t> used(tin_.vertices.size(), 0);
  for (size_t t = 0; t < tin_.triangles.size(); ++t)
    if (patch_.inside[t])
      for (uint32_t v : tin_.triangles[t].v) used[v] = 1;
  for (size_t i = 0; i < tin_.vertices.size(); ++i)
    if (ids_[i] == 0 && !used[i])
      return Status::Corruption("surface '" + ctx_.surface.name + "': the new vertex at " +
                                FormatPoint({tin_.vertices[i].x, tin_.vertices[i].y}) +
                                " fell outside the conflict region (kind " +
                                VertexKindName(tin_.vertices[i].kind) + ", round " +
                                std::to_string(patch_.rounds) + ")");
  return Status::Ok();
}

// New vertices (ring points, crossings, refinement points) get ids on from the largest, in local
// order; the region's existing vertices whose z changes (replace levels) are listed.
Status DeltaBuilder::NumberVertices() {
  std::vector<uint32_t> fresh;
  for (size_t i = 0; i < tin_.vertices.size(); ++i) {
    if (ids_[i] != 0) continue;
    const TinVertex& v = tin_.vertices[i];
    if (!std::isfinite(v.z))
      return Status::InvalidArgument("no elevation for the new vertex at " +
                                     FormatPoint({v.x, v.y}));
    fresh.push_back(static_cast<uint32_t>(i));
  }
  TB_ASSIGN_OR_RETURN(delta_.first_vertex,
                      MeshTables(ctx_.store.db(), ctx_.surface).NextVertexId(fresh.size()));
  for (size_t k = 0; k < fresh.size(); ++k) {
    ids_[fresh[k]] = delta_.first_vertex + static_cast<int64_t>(k);
    delta_.new_vertices.push_back(tin_.vertices[fresh[k]]);
  }
  for (size_t i = 0; i < tin_.vertices.size(); ++i) {
    if (patch_.store_ids[i] == 0) continue;
    TB_ASSIGN_OR_RETURN(const TinVertex* stored, ctx_.mesh.Vertex(patch_.store_ids[i]));
    if (stored->z == tin_.vertices[i].z) continue;
    TinVertex moved = *stored;
    moved.z = tin_.vertices[i].z;
    delta_.region_z.push_back({patch_.store_ids[i], moved});
  }
  return Status::Ok();
}

// The patch's inside triangles get ids on from the largest in the table, so an id never comes
// back with another triangle. Their rows go in block order, as a built surface's do, so that a
// later repaint of a block finds long runs of ids.
Status DeltaBuilder::NumberTriangles() {
  block_.assign(tin_.triangles.size(), 0);
  std::vector<std::pair<int64_t, uint32_t>> keyed;  // (block, local triangle)
  for (size_t t = 0; t < tin_.triangles.size(); ++t) {
    if (!patch_.inside[t]) continue;
    const auto& v = tin_.triangles[t].v;
    const TinVertex &a = tin_.vertices[v[0]], &b = tin_.vertices[v[1]], &c = tin_.vertices[v[2]];
    block_[t] = CentroidBlock(ctx_.surface.blocks, a.x, a.y, b.x, b.y, c.x, c.y);
    keyed.push_back({block_[t], static_cast<uint32_t>(t)});
  }
  std::sort(keyed.begin(), keyed.end());
  TB_ASSIGN_OR_RETURN(delta_.first_triangle,
                      MeshTables(ctx_.store.db(), ctx_.surface).NextTriangleId(keyed.size()));
  for (const auto& [b, t] : keyed) written_.push_back(t);
  new_id_.assign(tin_.triangles.size(), 0);
  for (size_t k = 0; k < written_.size(); ++k)
    new_id_[written_[k]] = delta_.first_triangle + static_cast<int64_t>(k);
  outer_across_.Reserve(patch_.outline.size());
  for (const OutlineEdge& e : patch_.outline)
    if (e.outer) outer_across_.Add(MeshEdge{e.a, e.b}, *e.outer);
  outer_across_.Seal();
  return Status::Ok();
}

// The paint of the new triangles and of the stored ones around the changed features (those of
// plan.around outside R; with outside_keeps_paint only those inside a changed feature), in one
// PaintFromFeatures over a Tin of both; their tags interned.
Result<Painting> DeltaBuilder::Paint() const {
  Painting out;
  Tin painted;
  std::unordered_map<int64_t, uint32_t> painted_vertex;
  painted_vertex.reserve(tin_.vertices.size() + plan_.around.size());
  const auto add_vertex = [&](int64_t id, const TinVertex& v) {
    auto [it, added] = painted_vertex.emplace(id, static_cast<uint32_t>(painted.vertices.size()));
    if (added) {
      painted.vertices.push_back(v);
      out.vertices.push_back(id);
    }
    return it->second;
  };
  for (uint32_t t : written_) {
    TinTriangle tri;
    for (int i = 0; i < 3; ++i)
      tri.v[i] = add_vertex(ids_[tin_.triangles[t].v[i]], tin_.vertices[tin_.triangles[t].v[i]]);
    painted.triangles.push_back(tri);
  }
  for (int64_t t : plan_.around) {
    if (region_.Has(t)) continue;
    TB_ASSIGN_OR_RETURN(const TriangleRow* stored, ctx_.mesh.Triangle(t));
    std::array<const TinVertex*, 3> corner;
    for (int i = 0; i < 3; ++i) {
      TB_ASSIGN_OR_RETURN(corner[i], ctx_.mesh.Vertex(stored->v[i]));
    }
    if (plan_.outside_keeps_paint) {
      const Point2 centroid{(corner[0]->x + corner[1]->x + corner[2]->x) / 3,
                            (corner[0]->y + corner[1]->y + corner[2]->y) / 3};
      if (plan_.changed_inside->Locate(centroid) == PointInPolygon::kOutside) continue;
    }
    TinTriangle tri;
    for (int i = 0; i < 3; ++i) tri.v[i] = add_vertex(stored->v[i], *corner[i]);
    painted.triangles.push_back(tri);
    out.kept_around.push_back(t);
  }
  out.paint = PaintFromFeatures(edit_.features, &patch_.grid, painted);
  for (const std::string& value : painted.tags) {
    TB_ASSIGN_OR_RETURN(int64_t id, InternTag(ctx_.store, value));
    out.tag_ids.push_back(id);
  }
  return out;
}

// The new triangles' rows: corners, links (to new triangles inside, across R's outline to the
// stored ones), paint and block.
void DeltaBuilder::TriangleRows(const Painting& painting) {
  delta_.new_triangles.resize(written_.size());
  for (size_t k = 0; k < written_.size(); ++k) {
    const TinTriangle& tri = tin_.triangles[written_[k]];
    TriangleRow& row = delta_.new_triangles[k];
    for (int i = 0; i < 3; ++i) {
      row.v[i] = ids_[tri.v[i]];
      if (tri.n[i] != kNoNeighbour && patch_.inside[tri.n[i]]) {
        row.n[i] = new_id_[tri.n[i]];
      } else {
        const MeshEdge across{ids_[tri.v[(i + 1) % 3]], ids_[tri.v[(i + 2) % 3]]};
        if (const int64_t* outer = outer_across_.Find(across)) row.n[i] = *outer;
      }
    }
    row.visible = painting.paint.visible[k] != 0;
    row.tag = painting.TagOf(k);
    row.block = block_[written_[k]];
  }
}

// The stored triangles across R's outline point at the new triangles.
Status DeltaBuilder::Relinks() {
  MeshEdgeTable inner_by_edge;  // store (a, b) -> new triangle
  // R's outline has no triangle across when R is the whole surface.
  if (!outer_across_.empty()) {
    for (uint32_t t : written_) {
      const auto& v = tin_.triangles[t].v;
      for (int i = 0; i < 3; ++i)
        inner_by_edge.Add(MeshEdge{ids_[v[i]], ids_[v[(i + 1) % 3]]}, new_id_[t]);
    }
  }
  inner_by_edge.Seal();
  std::map<int64_t, TriangleRow> relinked;
  for (const OutlineEdge& e : patch_.outline) {
    if (!e.outer) continue;
    const int64_t* inner = inner_by_edge.Find(MeshEdge{e.a, e.b});
    if (inner == nullptr)
      return Status::Corruption("outline edge (" + std::to_string(e.a) + ", " +
                                std::to_string(e.b) + ") vanished from the patch");
    auto [entry, fresh] = relinked.emplace(*e.outer, TriangleRow{});
    if (fresh) {
      TB_ASSIGN_OR_RETURN(const TriangleRow* outer, ctx_.mesh.Triangle(*e.outer));
      entry->second = *outer;
    }
    TriangleRow& outer = entry->second;
    for (int j = 0; j < 3; ++j)
      if (outer.v[(j + 1) % 3] == e.b && outer.v[(j + 2) % 3] == e.a) outer.n[j] = *inner;
  }
  delta_.relinked.assign(relinked.begin(), relinked.end());
  return Status::Ok();
}

// Constraint rows: the removed features' rows go; kept constraints split by new points or
// crossings are re-written piece by piece (for their owners and the features of new segments
// that run along them); the new polylines' pieces get their feature.
Status DeltaBuilder::Constraints() {
  delta_.removed_features = edit_.remove;
  graph_.assign(tin_.vertices.size(), {});
  for (const auto& [a, b] : tin_.constraints) graph_[a].push_back(b), graph_[b].push_back(a);
  // Sorted and made unique at the end (a large edit adds thousands: sets cost more).
  std::vector<std::pair<MeshEdge, int64_t>>& added = delta_.added_constraints;
  std::vector<MeshEdge> accounted;  // store edges that are constraints after the edit, or outline
  const auto add_row = [&](const MeshEdge& e, int64_t feature) {
    accounted.push_back(e);
    added.push_back({e, feature});
  };
  const auto add_pieces = [&](uint32_t a, uint32_t b, int64_t feature) -> Status {
    TB_ASSIGN_OR_RETURN(auto pieces, Pieces(graph_, tin_, a, b));
    for (const auto& [u, w] : pieces) add_row(EdgeKey(ids_[u], ids_[w]), feature);
    return Status::Ok();
  };
  // The features that new segments running along a kept constraint add to its owners.
  std::map<MeshEdge, std::vector<int64_t>> joining = region_.present;
  for (const auto& [edge, owners] : patch_.old_constraints) {
    const uint32_t a = patch_.local.at(edge.first), b = patch_.local.at(edge.second);
    std::vector<int64_t> joined;
    if (auto it = joining.find(edge); it != joining.end()) {
      joined = std::move(it->second);
      joining.erase(it);
    }
    if (std::find(graph_[a].begin(), graph_[a].end(), b) != graph_[a].end()) {
      accounted.push_back(edge);
      for (int64_t f : joined) add_row(edge, f);
      continue;
    }
    delta_.split_constraints.push_back(edge);
    for (int64_t f : owners) TB_RETURN_IF_ERROR(add_pieces(a, b, f));
    for (int64_t f : joined) TB_RETURN_IF_ERROR(add_pieces(a, b, f));
  }
  // Outside R the edge is as it was.
  for (const auto& [edge, features] : joining)
    for (int64_t f : features) add_row(edge, f);
  for (size_t l = 0; l < region_.lines.size(); ++l) {
    const std::vector<uint32_t>& idx = patch_.lines[l];
    const size_t n = idx.size();
    const size_t segments = region_.lines[l].closed ? n : n - 1;
    for (size_t i = 0; i < segments; ++i)
      if (idx[i] != idx[(i + 1) % n])
        TB_RETURN_IF_ERROR(add_pieces(idx[i], idx[(i + 1) % n], region_.lines[l].feature));
  }
  // No edge split above is among them (its pieces are).
  std::sort(added.begin(), added.end());
  added.erase(std::unique(added.begin(), added.end()), added.end());
  // The new triangles' other edges are unconstrained (for the cache; MeshCache::Apply).
  if (!region_.whole_surface) {
    for (uint32_t t : written_) {
      const auto& v = tin_.triangles[t].v;
      for (int i = 0; i < 3; ++i) {
        const uint32_t a = v[i], b = v[(i + 1) % 3];
        if (std::find(graph_[a].begin(), graph_[a].end(), b) == graph_[a].end())
          delta_.free_edges.push_back({ids_[a], ids_[b]});
      }
    }
  }
  // R's outline is constrained only in the patch; on the domain boundary new points may split
  // it (it has no triangle across), so its pieces count too.
  for (const OutlineEdge& e : patch_.outline) {
    TB_ASSIGN_OR_RETURN(auto pieces,
                        Pieces(graph_, tin_, patch_.local.at(e.a), patch_.local.at(e.b)));
    for (const auto& [u, w] : pieces) accounted.push_back(EdgeKey(ids_[u], ids_[w]));
  }
  return CheckNoConstraintRerouted(std::move(accounted));
}

// Every edge CGAL constrained must be one we own; one that is not means CGAL rerouted a
// constraint through another vertex (CGAL#6602) and the edge would be stored unconstrained.
Status DeltaBuilder::CheckNoConstraintRerouted(std::vector<MeshEdge> accounted) const {
  std::sort(accounted.begin(), accounted.end());
  for (const auto& [a, b] : tin_.constraints) {
    if (std::binary_search(accounted.begin(), accounted.end(), EdgeKey(ids_[a], ids_[b]))) continue;
    return Status::Corruption("surface '" + ctx_.surface.name +
                              "': a constraint was rerouted through " +
                              FormatPoint({tin_.vertices[a].x, tin_.vertices[a].y}) + " - " +
                              FormatPoint({tin_.vertices[b].x, tin_.vertices[b].y}) +
                              " while re-triangulating; nothing was written");
  }
  return Status::Ok();
}

// The stored triangles around whose paint changes, the uniform blocks' triangles, and the z of
// the painted vertices outside R that a replace feature sets or restores.
Status DeltaBuilder::Repaints(const Painting& painting) {
  size_t k = written_.size();  // paint index of the first stored triangle around
  for (size_t j = 0; j < painting.kept_around.size(); ++j, ++k) {
    TB_ASSIGN_OR_RETURN(const TriangleRow* stored, ctx_.mesh.Triangle(painting.kept_around[j]));
    const bool visible = painting.paint.visible[k] != 0;
    const std::optional<int64_t> tag = painting.TagOf(k);
    if (stored->visible != visible || stored->tag != tag)
      delta_.repaints.push_back({painting.kept_around[j], visible, tag});
  }
  std::sort(
      delta_.repaints.begin(), delta_.repaints.end(),
      [](const TriangleRepaint& a, const TriangleRepaint& b) { return a.triangle < b.triangle; });
  TB_ASSIGN_OR_RETURN(delta_.block_repaints,
                      UniformBlockRepaints(ctx_, plan_, region_.members, delta_));
  const int64_t end_new_vertex =
      delta_.first_vertex + static_cast<int64_t>(delta_.new_vertices.size());
  for (int64_t id : painting.vertices) {
    // R's vertices (existing or new) already have their z.
    if (patch_.local.count(id) || region_.dropped.count(id) ||
        (id >= delta_.first_vertex && id < end_new_vertex))
      continue;
    TB_ASSIGN_OR_RETURN(const TinVertex* stored, ctx_.mesh.Vertex(id));
    const double z = rules_.TargetZ(*stored);
    if (z == stored->z) continue;
    TinVertex moved = *stored;
    moved.z = z;
    delta_.around_z.push_back({id, moved});
  }
  return Status::Ok();
}

}  // namespace

Result<MeshDelta> BuildMeshDelta(const EditContext& ctx, const ElevationRules& rules,
                                 const LocalEdit& edit, const ConflictRegion& region,
                                 const LocalPatch& patch, const RepaintPlan& plan) {
  return DeltaBuilder(ctx, rules, edit, region, patch, plan).Run();
}

}  // namespace tinbase
