#include "db/edit/local_patch.h"

#include <algorithm>
#include <array>
#include <set>
#include <string>

#include "core/geometry/cdt.h"
#include "core/geometry/segment_index.h"
#include "core/geometry/triangle_tests.h"
#include "core/tin/region_outline.h"
#include "core/tin/tolerance_refiner.h"

namespace tinbase {
namespace {

// One re-triangulation of R: everything one round reads and builds. `carried` holds the
// refinement points of earlier rounds and receives this round's.
class Round {
 public:
  Round(const EditContext& ctx, const ElevationRules& rules, const std::vector<int64_t>& remove,
        const ConflictRegion& region, std::vector<TinVertex>* carried)
      : ctx_(ctx), rules_(rules), remove_(remove), region_(region), carried_(*carried) {}

  Result<LocalPatch> Run(const Box& paint_box) {
    TB_RETURN_IF_ERROR(CollectRegion(paint_box));
    if (region_.triangles.empty()) return std::move(patch_);  // a paint-only edit
    Cdt cdt;
    TB_RETURN_IF_ERROR(BuildCdt(cdt));
    Refine(cdt);
    return std::move(patch_);
  }

 private:
  Status CollectRegion(const Box& paint_box);
  Status BuildCdt(Cdt& cdt);
  void InsertSplitConstraint(Cdt& cdt, const MeshEdge& e);
  std::optional<uint32_t> LocalIndexOfNewPoint(const Point2& p) const;
  void Refine(Cdt& cdt);

  const EditContext& ctx_;
  const ElevationRules& rules_;
  const std::vector<int64_t>& remove_;
  const ConflictRegion& region_;
  std::vector<TinVertex>& carried_;
  LocalPatch patch_;
  std::vector<TinVertex> points_;  // R's stored vertices that stay, with their new z
  SegmentIndex outline_index_;
};

// R's vertices (local index i is points_[i]), outline and box, and the DEM under R and the paint
// box.
Status Round::CollectRegion(const Box& paint_box) {
  patch_.local.reserve(region_.triangles.size() * 2);
  std::vector<std::pair<Point2, Point2>> outline_segments;
  Box box = paint_box;
  for (int64_t t : region_.triangles) {
    TB_ASSIGN_OR_RETURN(const TriangleRow* tri, ctx_.mesh.Triangle(t));
    TriangleCorners corners;
    for (int i = 0; i < 3; ++i) {
      const int64_t id = tri->v[i];
      TB_ASSIGN_OR_RETURN(const TinVertex* v, ctx_.mesh.Vertex(id));
      corners[i] = {v->x, v->y};
      box.Add(corners[i]);
      patch_.region.Add(corners[i]);
      if (region_.dropped.count(id) || patch_.local.count(id)) continue;
      patch_.local.emplace(id, static_cast<uint32_t>(points_.size()));
      TinVertex copy = *v;
      copy.z = rules_.TargetZ(*v);
      points_.push_back(copy);
      patch_.store_ids.push_back(id);
    }
    for (int i = 0; i < 3; ++i) {
      const std::optional<int64_t>& n = tri->n[i];
      if (!n || !region_.Has(*n)) {
        patch_.outline.push_back({tri->v[(i + 1) % 3], tri->v[(i + 2) % 3], n});
        outline_segments.push_back({corners[(i + 1) % 3], corners[(i + 2) % 3]});
      }
    }
  }
  outline_index_.Build(std::move(outline_segments));
  const double cell = ctx_.Cell();
  return ctx_.dems.ReadWindow(
      ctx_.dem,
      {box.min_x - 2 * cell, box.min_y - 2 * cell, box.max_x + 2 * cell, box.max_y + 2 * cell}, 0,
      &patch_.grid);
}

// The CDT of R: its stored vertices, the new polylines' points (draped at their replace level),
// the refinement points of earlier rounds; R's outline, the kept constraints of R (split by the
// new points snapped onto them) and the new segments as constraints; crossings indexed.
Status Round::BuildCdt(Cdt& cdt) {
  cdt.InsertVertices(points_);  // distinct store vertices: local index i is points_[i]
  // Lone points (survey points, db/edit/mass_points.h) go in as one spatially sorted range:
  // thousands of one-point calls would each walk to their point from anywhere.
  std::vector<TinVertex> lone;
  std::vector<size_t> lone_lines;
  patch_.lines.resize(region_.lines.size());
  for (size_t l = 0; l < region_.lines.size(); ++l) {
    std::vector<TinVertex> draped = region_.lines[l].points;
    for (TinVertex& p : draped) {
      // Survey points (kUser, db/edit/mass_points.h) keep their kind: no removal of a
      // constraint through them may drop them.
      if (p.kind != VertexKind::kUser) p.kind = VertexKind::kRing;
      if (auto level = rules_.Level({p.x, p.y})) p.z = *level;
    }
    if (draped.size() == 1) {
      lone.push_back(draped.front());
      lone_lines.push_back(l);
      continue;
    }
    patch_.lines[l] = cdt.InsertVertices(draped);
  }
  if (!lone.empty()) {
    const std::vector<uint32_t> index = cdt.InsertVertices(lone);
    for (size_t k = 0; k < lone.size(); ++k) patch_.lines[lone_lines[k]] = {index[k]};
  }
  if (!carried_.empty()) cdt.InsertVertices(carried_);
  for (const OutlineEdge& e : patch_.outline)
    cdt.InsertConstraint(patch_.local.at(e.a), patch_.local.at(e.b));
  const std::set<int64_t> removing(remove_.begin(), remove_.end());
  for (int64_t t : region_.triangles) {
    TB_ASSIGN_OR_RETURN(const TriangleRow* tri, ctx_.mesh.Triangle(t));
    for (int i = 0; i < 3; ++i) {
      // An edge between two triangles of R is taken from the one with the smaller id.
      const std::optional<int64_t>& across = tri->n[(i + 2) % 3];
      if (across && *across < t && region_.Has(*across)) continue;
      const MeshEdge e = EdgeKey(tri->v[i], tri->v[(i + 1) % 3]);
      if (region_.removed_edges.count(e)) continue;
      TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* owners, ctx_.mesh.Owners(e.first, e.second));
      if (owners->empty()) continue;
      std::vector<int64_t> kept;
      for (int64_t f : *owners)
        if (!removing.count(f)) kept.push_back(f);
      InsertSplitConstraint(cdt, e);
      patch_.old_constraints.push_back({e, kept});
    }
  }
  for (size_t l = 0; l < region_.lines.size(); ++l) {
    const std::vector<uint32_t>& idx = patch_.lines[l];
    const size_t n = idx.size();
    const size_t segments = region_.lines[l].closed ? n : n - 1;
    for (size_t i = 0; i < segments; ++i)
      if (idx[i] != idx[(i + 1) % n]) cdt.InsertConstraint(idx[i], idx[(i + 1) % n]);
  }
  cdt.IndexCrossings([this](double x, double y) { return rules_.NewZ(x, y); });
  return Status::Ok();
}

// Kept constraint e, through the new points snapped onto it (region.splits) in order.
void Round::InsertSplitConstraint(Cdt& cdt, const MeshEdge& e) {
  std::vector<uint32_t> chain{patch_.local.at(e.first)};
  if (auto it = region_.splits.find(e); it != region_.splits.end()) {
    std::vector<std::pair<double, Point2>> points = it->second;
    std::sort(points.begin(), points.end(),
              [](const auto& l, const auto& r) { return l.first < r.first; });
    for (const auto& [along, p] : points)
      if (auto index = LocalIndexOfNewPoint(p)) chain.push_back(*index);
  }
  chain.push_back(patch_.local.at(e.second));
  for (size_t i = 0; i + 1 < chain.size(); ++i)
    if (chain[i] != chain[i + 1]) cdt.InsertConstraint(chain[i], chain[i + 1]);
}

// The local index of the polyline point at exactly `p`, if any.
std::optional<uint32_t> Round::LocalIndexOfNewPoint(const Point2& p) const {
  for (size_t l = 0; l < region_.lines.size(); ++l)
    for (size_t i = 0; i < region_.lines[l].points.size(); ++i)
      if (region_.lines[l].points[i].x == p.x && region_.lines[l].points[i].y == p.y)
        return patch_.lines[l][i];
  return std::nullopt;
}

// Refinement inside R only: the faces ClassifyInside finds now, and the faces refinement creates
// (each has a new vertex). A cell centre exactly on the outline is left alone: it would split an
// outline edge, and the triangle across already meets the tolerance there (both interpolate the
// same edge). Then the patch's Tin and which of its triangles are R's.
void Round::Refine(Cdt& cdt) {
  std::vector<std::pair<uint32_t, uint32_t>> outline_edges;
  for (const OutlineEdge& e : patch_.outline)
    outline_edges.push_back({patch_.local.at(e.a), patch_.local.at(e.b)});
  const DirectedOutline outline_local(points_.size(), outline_edges);
  const ElevationFn elevation = [this](double x, double y) { return rules_.NewZ(x, y); };
  const size_t before = cdt.vertices().size();
  Tin now = cdt.ToTin(elevation);
  std::vector<uint8_t> inside = ClassifyInside(now, outline_local);
  // R is the whole triangulation: no face to tell apart.
  const bool every_face_inside =
      std::all_of(inside.begin(), inside.end(), [](uint8_t c) { return c; });
  std::vector<std::array<uint32_t, 3>> inside_faces;  // corners sorted, then the list
  for (size_t t = 0; t < now.triangles.size() && !every_face_inside; ++t) {
    if (!inside[t]) continue;
    std::array<uint32_t, 3> key = now.triangles[t].v;
    std::sort(key.begin(), key.end());
    inside_faces.push_back(key);
  }
  std::sort(inside_faces.begin(), inside_faces.end());
  RefineOptions refine;
  refine.tolerance = ctx_.surface.tolerance.value_or(1.0);
  refine.excluded = [this](double x, double y) {
    return outline_index_.OnAny({x, y}) || rules_.ToleranceExempt({x, y});
  };
  if (!every_face_inside) {
    refine.in_region = [&](const std::array<uint32_t, 3>& v) {
      if (v[0] >= before || v[1] >= before || v[2] >= before) return true;
      std::array<uint32_t, 3> key = v;
      std::sort(key.begin(), key.end());
      return std::binary_search(inside_faces.begin(), inside_faces.end(), key);
    };
  }
  RefineToTolerance(cdt, patch_.grid, refine);
  for (size_t i = before; i < cdt.vertices().size(); ++i) carried_.push_back(cdt.vertices()[i]);
  patch_.refinement_points = static_cast<int64_t>(carried_.size());

  // Refinement only inserts points: with none inserted the triangulation is the one classified.
  const bool refined = cdt.vertices().size() != before;
  patch_.tin = refined ? cdt.ToTin(elevation) : std::move(now);
  patch_.store_ids.resize(patch_.tin.vertices.size(), 0);
  // Refinement adds points inside the faces it scans, so a triangulation that was all R stays so.
  if (every_face_inside)
    patch_.inside.assign(patch_.tin.triangles.size(), 1);
  else
    patch_.inside = refined ? ClassifyInside(patch_.tin, outline_local) : std::move(inside);
}

// The outer triangles that must join R: across an outline edge that the patch no longer has (a
// point split it) or that is not locally Delaunay (and not a kept constraint).
Result<std::vector<int64_t>> CheckOutline(MeshCache& mesh, const ConflictRegion& region,
                                          const LocalPatch& patch) {
  std::vector<int64_t> grow;
  const auto has_outer = [](const OutlineEdge& e) { return e.outer.has_value(); };
  if (std::none_of(patch.outline.begin(), patch.outline.end(), has_outer)) return grow;
  std::unordered_map<MeshEdge, uint32_t, MeshEdgeHash> directed;  // local (a, b) -> inside triangle
  for (size_t t = 0; t < patch.tin.triangles.size(); ++t) {
    if (!patch.inside[t]) continue;
    const auto& v = patch.tin.triangles[t].v;
    for (int i = 0; i < 3; ++i) directed.emplace(MeshEdge{v[i], v[(i + 1) % 3]}, t);
  }
  for (const OutlineEdge& e : patch.outline) {
    if (!e.outer) continue;
    const uint32_t a = patch.local.at(e.a), b = patch.local.at(e.b);
    auto it = directed.find(MeshEdge{a, b});
    if (it == directed.end()) {
      grow.push_back(*e.outer);
      continue;
    }
    TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* owners, mesh.Owners(e.a, e.b));
    if (!owners->empty() && !region.removed_edges.count(EdgeKey(e.a, e.b))) continue;
    TB_ASSIGN_OR_RETURN(const TriangleRow* outer, mesh.Triangle(*e.outer));
    int64_t far = outer->v[0];
    for (int64_t w : outer->v)
      if (w != e.a && w != e.b) far = w;
    TB_ASSIGN_OR_RETURN(Point2 fp, mesh.At(far));
    const TinTriangle& inner = patch.tin.triangles[it->second];
    const auto& p = patch.tin.vertices;
    if (InCircle({p[inner.v[0]].x, p[inner.v[0]].y}, {p[inner.v[1]].x, p[inner.v[1]].y},
                 {p[inner.v[2]].x, p[inner.v[2]].y}, fp) > 0)
      grow.push_back(*e.outer);
  }
  return grow;
}

}  // namespace

Result<LocalPatch> RetriangulateUntilSettled(const EditContext& ctx, const ElevationRules& rules,
                                             const Box& paint_box,
                                             const std::vector<int64_t>& remove,
                                             ConflictRegion* region) {
  std::vector<TinVertex> carried;  // refinement points of earlier rounds
  for (int rounds = 1;; ++rounds) {
    if (rounds > 200)
      return Status::Corruption("surface '" + ctx.surface.name +
                                "': the conflict region did not settle after 200 rounds");
    TB_ASSIGN_OR_RETURN(LocalPatch patch,
                        Round(ctx, rules, remove, *region, &carried).Run(paint_box));
    TB_ASSIGN_OR_RETURN(std::vector<int64_t> grow, CheckOutline(ctx.mesh, *region, patch));
    if (grow.empty()) {
      patch.rounds = rounds;
      return patch;
    }
    TB_RETURN_IF_ERROR(GrowAround(ctx.mesh, grow, region));
  }
}

}  // namespace tinbase
