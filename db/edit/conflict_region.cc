#include "db/edit/conflict_region.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <unordered_map>

#include "core/geometry/triangle_tests.h"
#include "db/mesh/mesh_tables.h"
#include "db/point_locator.h"

namespace tinbase {
namespace {

// A new polyline while R is seeded: a triangle holding each point, and the stored vertex each
// point snapped onto (0 for none).
struct SnappedLine {
  EditPolyline line;
  std::vector<int64_t> located;
  std::vector<int64_t> snapped_to;
};

// Finds R: each method is one step of FindConflictRegion, in the order Run calls them; region_
// is the value they build.
class RegionFinder {
 public:
  RegionFinder(const EditContext& ctx, const LocalEdit& edit)
      : ctx_(ctx),
        mesh_(ctx.mesh),
        edit_(edit),
        locator_(ctx.store, ctx.surface, &ctx.mesh),
        snap_(kSnapCells * ctx.Cell()) {}

  Result<ConflictRegion> Run() {
    TB_RETURN_IF_ERROR(SeedRemovals());
    TB_RETURN_IF_ERROR(SeedDroppedVertices());
    TB_RETURN_IF_ERROR(SeedRemovedReplaceInsides());
    for (int64_t t : edit_.seed) region_.Add(t);  // a resurvey's triangles over changed cells
    TB_RETURN_IF_ERROR(LoadSurfaceIfManyPoints());
    TB_RETURN_IF_ERROR(ReadBlocksAlongNewRings());
    TB_ASSIGN_OR_RETURN(std::vector<SnappedLine> lines, SnapPoints());
    TB_ASSIGN_OR_RETURN(lines, SetAsidePresentSegments(std::move(lines)));
    TB_ASSIGN_OR_RETURN(const std::vector<Point2> new_points, SeedPolylines(lines));
    // Growing by circumcircles only saves rounds of the local path; the whole surface needs none.
    TB_ASSIGN_OR_RETURN(bool whole, RegionIsMostOfTheSurface());
    if (!whole) {
      TB_RETURN_IF_ERROR(GrowByCircumcircles(new_points));
      TB_ASSIGN_OR_RETURN(whole, RegionIsMostOfTheSurface());
    }
    if (whole) TB_RETURN_IF_ERROR(TakeWholeSurface());
    for (SnappedLine& s : lines) region_.lines.push_back(std::move(s.line));
    return std::move(region_);
  }

 private:
  Result<int64_t> SurfaceTriangles();
  Status SeedRemovals();
  Result<bool> StillConstrained(int64_t v, const std::vector<int64_t>& star);
  Status SeedDroppedVertices();
  Status SeedRemovedReplaceInsides();
  Status LoadSurfaceIfManyPoints();
  Status ReadBlocksAlongNewRings();
  Result<bool> RegionIsMostOfTheSurface();
  Status TakeWholeSurface();
  template <typename Describe>
  Result<int64_t> Locate(const Point2& p, const Describe& what);
  Result<std::vector<SnappedLine>> SnapPoints();
  Result<bool> SnapOntoConstraint(int64_t t, TinVertex& p);
  Result<std::vector<SnappedLine>> SetAsidePresentSegments(std::vector<SnappedLine> lines);
  Result<bool> RunsAlongAConstraint(const SnappedLine& s, size_t i, size_t j);
  Result<std::vector<Point2>> SeedPolylines(std::vector<SnappedLine>& lines);
  Status WalkSegment(const Point2& p, const Point2& q, int64_t start,
                     std::vector<TinVertex>* on_segment);
  Status GrowByCircumcircles(const std::vector<Point2>& new_points);
  Result<TriangleCorners> Corners(int64_t t);

  const EditContext& ctx_;
  MeshCache& mesh_;
  const LocalEdit& edit_;
  PointLocator locator_;
  const double snap_;  // kSnapCells DEM cells
  ConflictRegion region_;
  std::optional<int64_t> surface_triangles_;  // SurfaceTriangles(), once counted
  std::vector<int64_t> surface_ids_;          // every triangle, once the surface is loaded
};

// The surface's triangles, counted once per edit (an index scan over the surface).
Result<int64_t> RegionFinder::SurfaceTriangles() {
  if (!surface_triangles_) {
    TB_ASSIGN_OR_RETURN(surface_triangles_,
                        MeshTables(ctx_.store.db(), ctx_.surface).CountTriangles());
  }
  return *surface_triangles_;
}

// The constraints of removed features go; the stars of their vertices join R, and ring or
// Steiner vertices left on no constraint are dropped.
Status RegionFinder::SeedRemovals() {
  const std::set<int64_t> removing(edit_.remove.begin(), edit_.remove.end());
  std::set<int64_t> touched;
  for (int64_t feature : edit_.remove) {
    TB_ASSIGN_OR_RETURN(std::vector<MeshEdge> edges, mesh_.EdgesOf(feature));
    for (const MeshEdge& e : edges) {
      TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* owners, mesh_.Owners(e.first, e.second));
      const bool gone = std::all_of(owners->begin(), owners->end(),
                                    [&](int64_t f) { return removing.count(f) > 0; });
      if (gone) region_.removed_edges.insert(e);
      touched.insert(e.first);
      touched.insert(e.second);
    }
  }
  for (int64_t v : touched) {
    TB_ASSIGN_OR_RETURN(const TinVertex* vertex, mesh_.Vertex(v));
    TB_ASSIGN_OR_RETURN(int64_t start, Locate({vertex->x, vertex->y},
                                              [v] { return "vertex " + std::to_string(v); }));
    bool closed = true;
    TB_ASSIGN_OR_RETURN(std::vector<int64_t> star, mesh_.Star(v, start, &closed));
    for (int64_t t : star) region_.Add(t);
    if (!closed || (vertex->kind != VertexKind::kRing && vertex->kind != VertexKind::kSteiner))
      continue;
    TB_ASSIGN_OR_RETURN(const bool constrained, StillConstrained(v, star));
    if (!constrained) region_.dropped.insert(v);
  }
  return Status::Ok();
}

// Whether an edge from `v` to a vertex of its star keeps a constraint after the edit.
Result<bool> RegionFinder::StillConstrained(int64_t v, const std::vector<int64_t>& star) {
  bool still_constrained = false;
  for (int64_t t : star) {
    TB_ASSIGN_OR_RETURN(const TriangleRow* tri, mesh_.Triangle(t));
    for (int64_t w : tri->v) {
      if (w == v || region_.removed_edges.count(EdgeKey(v, w))) continue;
      TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* owners, mesh_.Owners(v, w));
      if (!owners->empty()) still_constrained = true;
    }
  }
  return still_constrained;
}

// The stars of LocalEdit::drop_vertices join R; each goes unless a kept constraint ends at it.
Status RegionFinder::SeedDroppedVertices() {
  for (int64_t v : edit_.drop_vertices) {
    TB_ASSIGN_OR_RETURN(const TinVertex* vertex, mesh_.Vertex(v));
    TB_ASSIGN_OR_RETURN(int64_t start, Locate({vertex->x, vertex->y},
                                              [v] { return "vertex " + std::to_string(v); }));
    bool closed = true;
    TB_ASSIGN_OR_RETURN(std::vector<int64_t> star, mesh_.Star(v, start, &closed));
    for (int64_t t : star) region_.Add(t);
    if (!closed) continue;  // on the domain boundary: the hull needs it
    TB_ASSIGN_OR_RETURN(const bool constrained, StillConstrained(v, star));
    if (!constrained) region_.dropped.insert(v);
  }
  return Status::Ok();
}

// A removed replace feature's inside joins R: its vertices get their DEM z back and its cells
// must meet the tolerance again.
Status RegionFinder::SeedRemovedReplaceInsides() {
  std::vector<Polygon> polygons;
  Box box;
  for (int64_t id : edit_.remove) {
    auto f = LoadFeature(ctx_.store, ctx_.surface, id);  // REQUIRES: the row still exists
    if (!f.ok()) return f.status();
    region_.removed_features.push_back(std::move(*f));
    const EditorFeature& removed = region_.removed_features.back();
    if (removed.mode != FeatureMode::kReplace) continue;
    polygons.insert(polygons.end(), removed.polygons.begin(), removed.polygons.end());
    box.Add(BoxOf(removed));
  }
  if (polygons.empty()) return Status::Ok();
  auto restore = std::make_shared<const PolygonLocator>(polygons);
  region_.restore = restore;
  TB_ASSIGN_OR_RETURN(std::vector<int64_t> candidates, mesh_.TrianglesInBox(box));
  for (int64_t t : candidates) {
    TB_ASSIGN_OR_RETURN(const TriangleRow* tri, mesh_.Triangle(t));
    Point2 centroid{0, 0};
    for (int64_t v : tri->v) {
      TB_ASSIGN_OR_RETURN(Point2 p, mesh_.At(v));
      centroid.x += p.x / 3, centroid.y += p.y / 3;
    }
    if (restore->Locate(centroid) != PointInPolygon::kOutside) region_.Add(t);
  }
  return Status::Ok();
}

// An edit with at least a quarter as many new points as the surface has triangles touches a
// large part of it (each point lies in a triangle its segments cross), so every row is read in
// three scans (MeshCache::LoadSurface) instead of one lookup per row as the walks reach it: a
// scan costs a fraction of a lookup per row, and even if the region stays small the scan is about
// the cost of locating that many points. The same holds for the edits of a load applied one by
// one through a cache that keeps the rows (LocalEdit::load_points, which the caller sets only
// when the cache can keep them): the first reads the surface, the others find it held. Edits of
// fewer than kMinWholeSurfaceRegion points never count the surface's triangles.
Status RegionFinder::LoadSurfaceIfManyPoints() {
  if (mesh_.holds_whole_surface()) return Status::Ok();
  size_t own = 0;
  for (const EditPolyline& line : edit_.add) own += line.points.size();
  const size_t points = std::max(own, edit_.load_points);
  if (points < kMinWholeSurfaceRegion) return Status::Ok();
  TB_ASSIGN_OR_RETURN(const int64_t triangles, SurfaceTriangles());
  if (static_cast<int64_t>(points) * 4 < triangles) return Status::Ok();
  TB_ASSIGN_OR_RETURN(surface_ids_, mesh_.LoadSurface());
  region_.read_whole_surface = true;
  return Status::Ok();
}

// The blocks the added features' rings pass are read whole, with their triangles' vertices,
// before the walks along the rings (SnapPoints, SeedPolylines) look rows up one by one: the
// walks reach nearly only triangles of these blocks, and the repaint plan reads the blocks anyway
// (their triangles' paint may change).
Status RegionFinder::ReadBlocksAlongNewRings() {
  if (mesh_.holds_whole_surface()) return Status::Ok();
  std::set<int64_t> added;
  for (const EditPolyline& line : edit_.add) added.insert(line.feature);
  std::vector<int64_t> blocks;
  for (const EditorFeature& f : edit_.features) {
    if (!added.count(f.id)) continue;
    const std::vector<int64_t>& near = RingBlocksOf(f, ctx_.surface.blocks);
    blocks.insert(blocks.end(), near.begin(), near.end());
  }
  std::sort(blocks.begin(), blocks.end());
  blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
  return mesh_.ReadBlocks(blocks);
}

// Whether R as seeded holds more than half of the surface's triangles: the edit then
// re-triangulates the whole surface in one pass and rewrites its rows in bulk. Why half: past
// it, the rows the local path deletes and inserts one statement each (R twice, plus the links
// across R's outline and a re-triangulation of the growing R per round until its outline is
// Delaunay, three rounds for a whole map) cost more than deleting every triangle row in one
// statement and inserting all of them in batches after a single re-triangulation; and most
// triangle ids change either way (the tests of local edits demand that less than half of them
// do). Regions under kMinWholeSurfaceRegion triangles stay local without counting the surface.
Result<bool> RegionFinder::RegionIsMostOfTheSurface() {
  if (region_.triangles.size() < kMinWholeSurfaceRegion) return false;
  TB_ASSIGN_OR_RETURN(const int64_t triangles, SurfaceTriangles());
  return static_cast<int64_t>(region_.triangles.size()) * 2 > triangles;
}

// R becomes every triangle of the surface: its outline is then the domain boundary, with no
// triangle across, so one re-triangulation settles it, and no stored triangle is left to
// repaint (the paint of every new triangle is computed anyway).
Status RegionFinder::TakeWholeSurface() {
  if (surface_ids_.empty()) {
    TB_ASSIGN_OR_RETURN(surface_ids_, mesh_.LoadSurface());
    region_.read_whole_surface = true;
  }
  for (int64_t t : surface_ids_) region_.Add(t);
  region_.whole_surface = true;
  return Status::Ok();
}

// `what` names the point in the error (called only then: it is built for every ring point).
template <typename Describe>
Result<int64_t> RegionFinder::Locate(const Point2& p, const Describe& what) {
  auto located = locator_.LocateTriangle(p.x, p.y);
  if (located.ok()) return located->triangle;
  if (located.status().code() == StatusCode::kNotFound)
    return Status::InvalidArgument(what() + ": " + FormatPoint(p) + " lies outside surface '" +
                                   ctx_.surface.name + "'");
  return located.status();
}

// Moves each new point within the snap distance of an existing vertex (of the triangle holding
// it) or of an earlier new point onto it, so near-duplicates (rings of neighbouring features
// digitised or reprojected apart by round-off) become one vertex instead of a sliver; else onto
// a kept constraint that close (SnapOntoConstraint). Locates every point on the way.
Result<std::vector<SnappedLine>> RegionFinder::SnapPoints() {
  std::unordered_map<std::pair<int64_t, int64_t>, std::vector<Point2>, MeshEdgeHash> buckets;
  const double snap = snap_;
  const auto bucket = [snap](double v) { return static_cast<int64_t>(std::floor(v / snap)); };
  std::vector<SnappedLine> lines;
  for (const EditPolyline& input : edit_.add) {
    lines.push_back({input, {}, {}});
    SnappedLine& out = lines.back();
    EditPolyline& line = out.line;
    std::optional<int64_t> previous;  // the triangle holding the previous point
    for (size_t i = 0; i < line.points.size(); ++i) {
      TinVertex& p = line.points[i];
      const auto what = [&line, i] {
        return "feature " + std::to_string(line.feature) + ", point " + std::to_string(i);
      };
      // Draped ring points lie a DEM cell or less apart, often several in one triangle; a point
      // strictly inside the previous point's triangle lies in no other, so the locator would
      // return that triangle: no walk.
      bool same = false;
      if (previous) {
        TB_ASSIGN_OR_RETURN(const TriangleCorners c, Corners(*previous));
        same = StrictlyInside(c, {p.x, p.y});
      }
      int64_t t = previous.value_or(0);
      if (!same) {
        TB_ASSIGN_OR_RETURN(t, Locate({p.x, p.y}, what));
      }
      TB_ASSIGN_OR_RETURN(const TriangleRow* tri, mesh_.Triangle(t));
      bool snapped = false;
      int64_t vertex = 0;
      for (int64_t v : tri->v) {
        TB_ASSIGN_OR_RETURN(Point2 q, mesh_.At(v));
        if (std::hypot(q.x - p.x, q.y - p.y) > snap) continue;
        p.x = q.x, p.y = q.y;
        snapped = true;
        vertex = v;
        break;
      }
      const int64_t bx = bucket(p.x), by = bucket(p.y);
      for (int64_t j = by - 1; j <= by + 1 && !snapped; ++j) {
        for (int64_t k = bx - 1; k <= bx + 1 && !snapped; ++k) {
          auto it = buckets.find({k, j});
          if (it == buckets.end()) continue;
          for (const Point2& q : it->second) {
            if (std::hypot(q.x - p.x, q.y - p.y) > snap) continue;
            p.x = q.x, p.y = q.y;
            snapped = true;
            // q may lie in another triangle than p did.
            TB_ASSIGN_OR_RETURN(t, Locate(q, what));
            break;
          }
        }
      }
      if (!snapped) {
        TB_ASSIGN_OR_RETURN(snapped, SnapOntoConstraint(t, p));
      }
      buckets[{bx, by}].push_back({p.x, p.y});
      out.located.push_back(t);
      out.snapped_to.push_back(vertex);
      previous = t;
    }
  }
  return lines;
}

// Moves `p` onto a kept constrained edge closer than the snap distance (of triangle `t` or a
// neighbour, not near its ends, not on the domain boundary) and records that the edge is to be
// split there: left where it was, p would sit a hair beside the edge and make a sliver (or a
// crossing a hair away from it). Both triangles of the edge join R, so the split stays inside it.
// The projection lies on the edge only up to round-off, which the walk along split constraints
// (db/edit/mesh_delta_builder.cc) allows for.
Result<bool> RegionFinder::SnapOntoConstraint(int64_t t, TinVertex& p) {
  TB_ASSIGN_OR_RETURN(const TriangleRow* holding, mesh_.Triangle(t));
  std::vector<int64_t> candidates{t};
  for (const std::optional<int64_t>& n : holding->n)
    if (n) candidates.push_back(*n);
  for (int64_t c : candidates) {
    TB_ASSIGN_OR_RETURN(const TriangleRow* tri, mesh_.Triangle(c));
    const TriangleRow here = *tri;
    for (int i = 0; i < 3; ++i) {
      if (!here.n[i]) continue;
      const int64_t a = here.v[(i + 1) % 3], b = here.v[(i + 2) % 3];
      // Distance first: the constraint lookup reads rows, and nearly every edge is too far.
      TB_ASSIGN_OR_RETURN(const Point2 pa, mesh_.At(a));
      TB_ASSIGN_OR_RETURN(const Point2 pb, mesh_.At(b));
      const double dx = pb.x - pa.x, dy = pb.y - pa.y, len = std::hypot(dx, dy);
      if (len == 0) continue;
      const double along = ((p.x - pa.x) * dx + (p.y - pa.y) * dy) / (len * len);
      const double off = std::fabs((p.x - pa.x) * dy - (p.y - pa.y) * dx) / len;
      const double ends = snap_ / len;
      if (along <= ends || along >= 1 - ends || off > snap_) continue;
      if (region_.removed_edges.count(EdgeKey(a, b))) continue;
      TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* owners, mesh_.Owners(a, b));
      if (owners->empty()) continue;
      p.x = pa.x + along * dx, p.y = pa.y + along * dy;
      region_.splits[EdgeKey(a, b)].push_back({a < b ? along : 1 - along, Point2{p.x, p.y}});
      region_.Add(c);
      region_.Add(*here.n[i]);
      return true;
    }
  }
  return false;
}

// A new segment whose ends snapped onto the two ends of a kept constrained edge runs exactly
// along it: the shared boundary of neighbouring polygons, half the segments of a map layer
// loaded feature by feature. Constraining an edge that already is one leaves the CDT as it is,
// so such a segment seeds no conflict region; it only gains an owner (region.present), whose row
// the delta adds, piece by piece if R's re-triangulation splits the edge. The rest of its line
// goes on as open chains of the other segments. Off while the surface has replace features or
// the edit removes any: both change vertex z, which only R and the paint area settle.
Result<std::vector<SnappedLine>> RegionFinder::SetAsidePresentSegments(
    std::vector<SnappedLine> lines) {
  bool has_replace = false;
  for (const EditorFeature& f : edit_.features)
    has_replace |= f.mode == FeatureMode::kReplace && !f.polygons.empty();
  if (has_replace || !edit_.remove.empty()) return lines;
  std::vector<SnappedLine> chains;
  for (SnappedLine& s : lines) {
    const EditPolyline& line = s.line;
    const size_t n = line.points.size();
    const size_t segments = line.closed ? n : (n > 0 ? n - 1 : 0);
    std::vector<uint8_t> present(segments, 0);
    for (size_t i = 0; i < segments; ++i) {
      TB_ASSIGN_OR_RETURN(const bool along, RunsAlongAConstraint(s, i, (i + 1) % n));
      present[i] = along;
    }
    const auto first_present = std::find(present.begin(), present.end(), uint8_t{1});
    if (first_present == present.end()) {
      chains.push_back(std::move(s));
      continue;
    }
    // A closed line's chains start after a present segment, so none wraps around.
    const size_t start = line.closed ? static_cast<size_t>(first_present - present.begin()) + 1 : 0;
    SnappedLine chain{EditPolyline{{}, false, line.feature}, {}, {}};
    const auto end_chain = [&] {
      if (!chain.line.points.empty()) chains.push_back(std::move(chain));
      chain = SnappedLine{EditPolyline{{}, false, line.feature}, {}, {}};
    };
    for (size_t k = 0; k < segments; ++k) {
      const size_t i = (start + k) % segments, j = (i + 1) % n;
      if (present[i]) {
        const int64_t a = s.snapped_to[i], b = s.snapped_to[j];
        if (a != b) region_.present[EdgeKey(a, b)].push_back(line.feature);
        end_chain();
        continue;
      }
      if (chain.line.points.empty()) {
        chain.line.points.push_back(line.points[i]);
        chain.located.push_back(s.located[i]);
      }
      chain.line.points.push_back(line.points[j]);
      chain.located.push_back(s.located[j]);
    }
    end_chain();
  }
  for (SnappedLine& chain : chains) chain.snapped_to.clear();  // no longer matches the points
  return chains;
}

// Whether the segment from point i to point j of `s` lies on a kept constrained edge: both ends
// snapped onto its vertices (or onto one vertex: a segment of length 0), and no point of this
// edit splits it.
Result<bool> RegionFinder::RunsAlongAConstraint(const SnappedLine& s, size_t i, size_t j) {
  const int64_t a = s.snapped_to[i], b = s.snapped_to[j];
  if (a == 0 || b == 0) return false;
  if (a == b) return true;
  const MeshEdge e = EdgeKey(a, b);
  if (region_.removed_edges.count(e) || region_.splits.count(e) || region_.dropped.count(a) ||
      region_.dropped.count(b))
    return false;
  TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* owners, mesh_.Owners(a, b));
  return !owners->empty();
}

// Every triangle a new segment touches (closed: a segment through a vertex takes its fan), found
// by a walk over neighbours from the triangle holding the segment's first point. Existing
// vertices closer than the snap distance to a new segment (but not its ends) become points of
// it: a crossing vertex an earlier edit constructed lies only nearly on the line, and CGAL would
// otherwise reroute the constraint through another vertex (CGAL#6602). Returns the new points,
// those included.
Result<std::vector<Point2>> RegionFinder::SeedPolylines(std::vector<SnappedLine>& lines) {
  std::vector<Point2> new_points;
  for (SnappedLine& s : lines) {
    EditPolyline& line = s.line;
    const size_t n = line.points.size();
    const size_t segments = line.closed ? n : n - 1;
    std::vector<TinVertex> points;
    // A lone point (a survey point) has no segment to walk: its triangle seeds R.
    if (n == 1) region_.Add(s.located[0]);
    for (size_t i = 0; i < n; ++i) {
      const Point2 p{line.points[i].x, line.points[i].y};
      points.push_back(line.points[i]);
      new_points.push_back(p);
      if (i >= segments) continue;
      const Point2 q{line.points[(i + 1) % n].x, line.points[(i + 1) % n].y};
      std::vector<TinVertex> on_segment;
      TB_RETURN_IF_ERROR(WalkSegment(p, q, s.located[i], &on_segment));
      for (const TinVertex& w : on_segment) {
        points.push_back(w);
        new_points.push_back({w.x, w.y});
      }
    }
    line.points = std::move(points);
  }
  return new_points;
}

// Adds the triangles segment pq touches to R, walking from `start` (holding p); `on_segment`
// receives the existing vertices within the snap distance of pq, away from its ends, in order
// along it.
Status RegionFinder::WalkSegment(const Point2& p, const Point2& q, int64_t start,
                                 std::vector<TinVertex>* on_segment) {
  std::vector<int64_t> queue{start};
  std::unordered_set<int64_t> seen{start};
  std::map<double, TinVertex> by_along;  // by position along pq
  const double dx = q.x - p.x, dy = q.y - p.y, len2 = dx * dx + dy * dy;
  while (!queue.empty()) {
    const int64_t t = queue.back();
    queue.pop_back();
    region_.Add(t);
    TB_ASSIGN_OR_RETURN(const TriangleRow* tri, mesh_.Triangle(t));
    for (int64_t v : tri->v) {
      TB_ASSIGN_OR_RETURN(const TinVertex* w, mesh_.Vertex(v));
      if (len2 == 0) break;
      const double along = ((w->x - p.x) * dx + (w->y - p.y) * dy) / len2;
      const double off = std::fabs((w->x - p.x) * dy - (w->y - p.y) * dx) / std::sqrt(len2);
      const double ends = snap_ / std::sqrt(len2);
      if (along > ends && along < 1 - ends && off <= snap_) by_along.emplace(along, *w);
    }
    for (const std::optional<int64_t>& next : tri->n) {
      if (!next || !seen.insert(*next).second) continue;
      TB_ASSIGN_OR_RETURN(const TriangleCorners c, Corners(*next));
      if (SegmentMeetsTriangle(p, q, c[0], c[1], c[2])) queue.push_back(*next);
    }
  }
  for (const auto& [along, w] : by_along) on_segment->push_back(w);
  return Status::Ok();
}

// Grows R across unconstrained outline edges by the triangles whose circumcircle strictly holds
// a new point (the Bowyer-Watson cavity): they cannot survive the insertion. Later rounds catch
// anything this misses (refinement points), so this only saves rounds.
Status RegionFinder::GrowByCircumcircles(const std::vector<Point2>& new_points) {
  if (new_points.empty()) return Status::Ok();
  std::vector<Point2> points = new_points;
  std::sort(points.begin(), points.end(),
            [](const Point2& a, const Point2& b) { return a.x < b.x; });
  for (size_t k = 0; k < region_.triangles.size(); ++k) {
    const int64_t t = region_.triangles[k];
    TB_ASSIGN_OR_RETURN(const TriangleRow* tri, mesh_.Triangle(t));
    const TriangleRow here = *tri;
    for (int i = 0; i < 3; ++i) {
      if (!here.n[i] || region_.Has(*here.n[i])) continue;
      const int64_t a = here.v[(i + 1) % 3], b = here.v[(i + 2) % 3];
      TB_ASSIGN_OR_RETURN(const TriangleCorners c, Corners(*here.n[i]));
      if (!CircleHoldsAny(c, points)) continue;
      // A kept constraint shields the triangle across (checked second: it reads a row).
      TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* owners, mesh_.Owners(a, b));
      if (!owners->empty() && !region_.removed_edges.count(EdgeKey(a, b))) continue;
      region_.Add(*here.n[i]);
    }
  }
  return Status::Ok();
}

Result<TriangleCorners> RegionFinder::Corners(int64_t t) {
  TB_ASSIGN_OR_RETURN(const TriangleRow* tri, mesh_.Triangle(t));
  TriangleCorners c;
  for (int i = 0; i < 3; ++i) {
    TB_ASSIGN_OR_RETURN(c[i], mesh_.At(tri->v[i]));
  }
  return c;
}

}  // namespace

Result<ConflictRegion> FindConflictRegion(const EditContext& ctx, const LocalEdit& edit) {
  RegionFinder finder(ctx, edit);
  return finder.Run();
}

Status GrowAround(MeshCache& mesh, const std::vector<int64_t>& failed, ConflictRegion* region) {
  std::vector<int64_t> ring = failed;
  for (int depth = 0; depth < 2; ++depth) {
    std::vector<int64_t> next;
    for (int64_t t : ring) {
      region->Add(t);
      TB_ASSIGN_OR_RETURN(const TriangleRow* tri, mesh.Triangle(t));
      const TriangleRow here = *tri;
      for (const std::optional<int64_t>& n : here.n)
        if (n && !region->Has(*n)) next.push_back(*n);
    }
    ring = std::move(next);
  }
  for (int64_t t : ring) region->Add(t);
  return Status::Ok();
}

}  // namespace tinbase
