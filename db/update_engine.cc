#include "db/update_engine.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "core/geometry/cdt.h"
#include "core/geometry/polygon_locator.h"
#include "core/geometry/predicates.h"
#include "core/tin/cell_cover.h"
#include "core/tin/feature_paint.h"
#include "core/tin/ring_blocks.h"
#include "core/tin/tolerance_refiner.h"
#include "db/mesh_cache.h"
#include "db/point_locator.h"
#include "db/sqlite/bulk_write.h"
#include "db/sqlite/unchecked_foreign_keys.h"

namespace tinbase {

namespace {

using Edge = std::pair<int64_t, int64_t>;  // (min, max) store vertex ids, or a directed pair

Edge Key(int64_t a, int64_t b) { return {std::min(a, b), std::max(a, b)}; }

struct EdgeHash {
  size_t operator()(const Edge& e) const {
    return std::hash<int64_t>()(e.first) * 1000003u ^ std::hash<int64_t>()(e.second);
  }
};

using Corners3 = std::array<Point2, 3>;

// Edges to ids, looked up by binary search: each edit builds a few once and reads them many
// times, and a hash map spent a heap node per entry.
class EdgeTable {
 public:
  void Reserve(size_t n) { entries_.reserve(n); }
  void Add(const Edge& e, int64_t id) { entries_.emplace_back(e, id); }
  // REQUIRES: called after the last Add and before the first Find.
  void Seal() { std::sort(entries_.begin(), entries_.end()); }
  // The id of edge `e`, or null.
  const int64_t* Find(const Edge& e) const {
    auto it =
        std::lower_bound(entries_.begin(), entries_.end(), e,
                         [](const auto& entry, const Edge& key) { return entry.first < key; });
    return it != entries_.end() && it->first == e ? &it->second : nullptr;
  }
  bool empty() const { return entries_.empty(); }

 private:
  std::vector<std::pair<Edge, int64_t>> entries_;
};

// True when the closed segment pq and the closed counter-clockwise triangle abc share a point:
// no separating line among pq's and the triangle's edges (exact).
bool SegmentMeetsTriangle(const Point2& p, const Point2& q, const Point2& a, const Point2& b,
                          const Point2& c) {
  const int oa = Orientation(p, q, a), ob = Orientation(p, q, b), oc = Orientation(p, q, c);
  if ((oa > 0 && ob > 0 && oc > 0) || (oa < 0 && ob < 0 && oc < 0)) return false;
  const Point2* v[3] = {&a, &b, &c};
  for (int i = 0; i < 3; ++i) {
    const Point2& x = *v[i];
    const Point2& y = *v[(i + 1) % 3];
    if (Orientation(x, y, p) < 0 && Orientation(x, y, q) < 0) return false;
  }
  return true;
}

// Answers "does this point lie exactly on one of these segments" (R's outline), through a coarse
// bucket grid; exact orientation tests.
class SegmentIndex {
 public:
  void Build(std::vector<std::pair<Point2, Point2>> segments) {
    segments_ = std::move(segments);
    box_ = Box();
    for (const auto& [a, b] : segments_) box_.Add(a), box_.Add(b);
    side_ = std::max<int64_t>(1, static_cast<int64_t>(std::sqrt(segments_.size())));
    cells_.assign(static_cast<size_t>(side_ * side_), {});
    for (uint32_t k = 0; k < segments_.size(); ++k) {
      Box b;
      b.Add(segments_[k].first), b.Add(segments_[k].second);
      for (int64_t r = Row(b.min_y); r <= Row(b.max_y); ++r)
        for (int64_t c = Col(b.min_x); c <= Col(b.max_x); ++c) cells_[r * side_ + c].push_back(k);
    }
  }

  bool OnAny(const Point2& p) const {
    if (!box_.Contains(p)) return false;
    for (uint32_t k : cells_[Row(p.y) * side_ + Col(p.x)]) {
      const auto& [a, b] = segments_[k];
      Box s;
      s.Add(a), s.Add(b);
      if (s.Contains(p) && Orientation(a, b, p) == 0) return true;
    }
    return false;
  }

 private:
  int64_t Col(double x) const { return Index(x, box_.min_x, box_.max_x); }
  int64_t Row(double y) const { return Index(y, box_.min_y, box_.max_y); }
  int64_t Index(double v, double lo, double hi) const {
    if (!(hi > lo)) return 0;
    return std::clamp<int64_t>(static_cast<int64_t>((v - lo) / (hi - lo) * side_), 0, side_ - 1);
  }

  std::vector<std::pair<Point2, Point2>> segments_;
  Box box_;
  int64_t side_ = 1;
  std::vector<std::vector<uint32_t>> cells_;
};

// R's outline in local vertex indices, directed as R's triangles have it: each vertex's
// outgoing edges (one or two, seldom more) in one array, so a lookup reads a few entries
// instead of hashing (ClassifyInside asks six times a triangle).
class DirectedOutline {
 public:
  DirectedOutline(size_t vertices, const std::vector<std::pair<uint32_t, uint32_t>>& edges)
      : first_(vertices + 1, 0), to_(edges.size()) {
    for (const auto& [a, b] : edges) ++first_[a + 1];
    for (size_t v = 0; v < vertices; ++v) first_[v + 1] += first_[v];
    std::vector<uint32_t> next(first_.begin(), first_.end() - 1);
    for (const auto& [a, b] : edges) to_[next[a]++] = b;
  }
  // Whether (a, b) is an outline edge in that direction.
  bool Has(uint32_t a, uint32_t b) const {
    if (a + 1 >= first_.size()) return false;
    for (uint32_t k = first_[a]; k < first_[a + 1]; ++k)
      if (to_[k] == b) return true;
    return false;
  }

 private:
  std::vector<uint32_t> first_;  // per vertex, where its edges start in to_
  std::vector<uint32_t> to_;
};

// Which triangles of a local triangulation lie in R, from R's outline alone: a triangle with an
// outline edge in R's direction is inside, with it reversed outside, and the rest take the class
// of their neighbours across edges that are not on the outline. Purely topological, so a sliver
// outside R along a nearly straight outline is never taken for part of it.
std::vector<uint8_t> ClassifyInside(const Tin& tin, const DirectedOutline& outline) {
  constexpr uint8_t kUnknown = 2;
  std::vector<uint8_t> inside(tin.triangles.size(), kUnknown);
  std::vector<uint32_t> queue;
  for (uint32_t t = 0; t < tin.triangles.size(); ++t) {
    const auto& v = tin.triangles[t].v;
    for (int i = 0; i < 3 && inside[t] == kUnknown; ++i) {
      const uint32_t a = v[i], b = v[(i + 1) % 3];
      if (outline.Has(a, b))
        inside[t] = 1;
      else if (outline.Has(b, a))
        inside[t] = 0;
    }
    if (inside[t] != kUnknown) queue.push_back(t);
  }
  while (!queue.empty()) {
    const uint32_t t = queue.back();
    queue.pop_back();
    const TinTriangle& tri = tin.triangles[t];
    for (int i = 0; i < 3; ++i) {
      const int32_t n = tri.n[i];
      if (n == kNoNeighbour || inside[n] != kUnknown) continue;
      const uint32_t a = tri.v[(i + 1) % 3], b = tri.v[(i + 2) % 3];
      if (outline.Has(a, b) || outline.Has(b, a)) continue;
      inside[n] = inside[t];
      queue.push_back(static_cast<uint32_t>(n));
    }
  }
  for (uint8_t& c : inside)
    if (c == kUnknown) c = 0;
  return inside;
}

// z where a replace feature covers a point: the last one in id order wins (as in painting).
class ReplaceLevels {
 public:
  explicit ReplaceLevels(const std::vector<EditorFeature>& features) {
    for (const EditorFeature& f : features) {
      if (f.mode != FeatureMode::kReplace) continue;
      locators_.push_back(InsideOf(f));
      levels_.push_back(f.level.value_or(0));
    }
  }
  std::optional<double> At(const Point2& p) const {
    for (size_t k = locators_.size(); k-- > 0;)
      if (locators_[k]->Locate(p) != PointInPolygon::kOutside) return levels_[k];
    return std::nullopt;
  }
  bool empty() const { return locators_.empty(); }

 private:
  std::vector<std::shared_ptr<const PolygonLocator>> locators_;
  std::vector<double> levels_;
};

// An outline edge of R: the directed edge a->b of a triangle of R, and the stored triangle across
// it (none on the domain boundary).
struct OutlineEdge {
  int64_t a = 0, b = 0;
  std::optional<int64_t> outer;
};

// One re-triangulation of R: the local Tin and how its vertices map to the store.
struct LocalPatch {
  Tin tin;                                   // local CDT, constraints include R's outline
  std::vector<uint8_t> inside;               // per local triangle: part of R
  std::vector<int64_t> store_ids;            // per local vertex: store id, 0 for a new vertex
  std::vector<std::vector<uint32_t>> lines;  // local index of each polyline point
  std::vector<std::pair<Edge, std::vector<int64_t>>> old_constraints;  // kept, in R, owners
  int64_t refinement_points = 0;
};

class Edit {
 public:
  Edit(Store& store, const SurfaceInfo& surface, DemStore& dems, const DemInfo& dem,
       const LocalEdit& edit, const FaultHook& hook, std::unique_ptr<ScopedPageCache>& page_cache,
       MeshCache& mesh)
      : store_(store),
        surface_(surface),
        dems_(dems),
        dem_(dem),
        edit_(edit),
        hook_(hook),
        page_cache_(page_cache),
        mesh_(mesh),
        locator_(store, surface, &mesh),
        levels_(edit.features),
        lines_(edit.add) {
    for (const EditorFeature& f : edit.features)
      if (f.mode == FeatureMode::kReplace)
        replace_polygons_.insert(replace_polygons_.end(), f.polygons.begin(), f.polygons.end());
    replaced_ = std::make_unique<PolygonLocator>(replace_polygons_);
  }

  Result<EditResult> Run() {
    TB_RETURN_IF_ERROR(SeedRemovals());
    TB_RETURN_IF_ERROR(LoadSurfaceIfManyPoints());
    TB_RETURN_IF_ERROR(ReadBlocksAlongNewRings());
    TB_RETURN_IF_ERROR(SnapPoints());
    TB_RETURN_IF_ERROR(SetAsidePresentSegments());
    TB_RETURN_IF_ERROR(SeedPolylines());
    // Growing by circumcircles only saves rounds of the local path; the whole surface needs none.
    TB_ASSIGN_OR_RETURN(whole_surface_, RegionIsMostOfTheSurface());
    if (!whole_surface_) {
      TB_RETURN_IF_ERROR(GrowByCircumcircles());
      TB_ASSIGN_OR_RETURN(whole_surface_, RegionIsMostOfTheSurface());
    }
    if (whole_surface_) {
      TB_RETURN_IF_ERROR(TakeWholeSurface());
    } else {
      TB_RETURN_IF_ERROR(FindPaintArea());
    }
    LocalPatch patch;
    for (result_.rounds = 1;; ++result_.rounds) {
      if (result_.rounds > 200)
        return Status::Corruption("surface '" + surface_.name +
                                  "': the conflict region did not settle after 200 rounds");
      TB_ASSIGN_OR_RETURN(patch, Retriangulate());
      TB_ASSIGN_OR_RETURN(std::vector<int64_t> grow, CheckOutline(patch));
      if (grow.empty()) break;
      TB_RETURN_IF_ERROR(GrowAround(grow));
    }
    result_.refinement_points = patch.refinement_points;
    TB_RETURN_IF_ERROR(Write(patch));
    result_.whole_surface = whole_surface_;
    return result_;
  }

 private:
  // --- finding R ---------------------------------------------------------------------------

  // The surface's triangles, counted once per edit (an index scan: ~0.1 us a triangle).
  Result<int64_t> SurfaceTriangles() {
    if (!surface_triangles_) {
      TB_ASSIGN_OR_RETURN(Statement * count,
                          store_.db().Cached("SELECT count(*) FROM triangles WHERE surface = ?"));
      count->Bind(1, surface_.id);
      TB_ASSIGN_OR_RETURN(bool row, count->Step());
      surface_triangles_ = row ? count->ColumnInt(0) : 0;
      count->Reset();
    }
    return *surface_triangles_;
  }

  // The blocks the added features' rings pass are read whole, with their triangles' vertices,
  // before the walks along the rings (SnapPoints, SeedPolylines) look rows up one by one: the
  // walks reach nearly only triangles of these blocks, and FindPaintArea reads the blocks anyway
  // (their triangles' paint may change).
  Status ReadBlocksAlongNewRings() {
    if (mesh_.holds_whole_surface()) return Status::Ok();
    std::set<int64_t> added;
    for (const EditPolyline& line : edit_.add) added.insert(line.feature);
    std::vector<int64_t> blocks;
    for (const EditorFeature& f : edit_.features) {
      if (!added.count(f.id)) continue;
      const std::vector<int64_t>& near = RingBlocksOf(f, surface_.blocks);
      blocks.insert(blocks.end(), near.begin(), near.end());
    }
    std::sort(blocks.begin(), blocks.end());
    blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
    return mesh_.ReadBlocks(blocks);
  }

  // An edit with at least a quarter as many new points as the surface has triangles touches a
  // large part of it (each point lies in a triangle its segments cross), so every row is read
  // in three scans (MeshCache::LoadSurface) instead of one lookup per row as the walks reach it:
  // a scan costs a fraction of a lookup per row, and even if the region stays small the scan is
  // about the cost of locating that many points. The same holds for the edits of a load applied
  // one by one through a cache that keeps the rows (LocalEdit::load_points, which the caller
  // sets only when the cache can keep them): the first reads the surface, the others find it
  // held. Edits of fewer than kMinWholeSurfaceRegion points never count the surface's triangles.
  Status LoadSurfaceIfManyPoints() {
    if (mesh_.holds_whole_surface()) return Status::Ok();
    size_t own = 0;
    for (const EditPolyline& line : lines_) own += line.points.size();
    const size_t points = std::max(own, edit_.load_points);
    if (points < kMinWholeSurfaceRegion) return Status::Ok();
    TB_ASSIGN_OR_RETURN(const int64_t triangles, SurfaceTriangles());
    if (static_cast<int64_t>(points) * 4 < triangles) return Status::Ok();
    TB_ASSIGN_OR_RETURN(surface_ids_, mesh_.LoadSurface());
    result_.read_whole_surface = true;
    return Status::Ok();
  }

  // Whether R as seeded holds more than half of the surface's triangles: the edit then
  // re-triangulates the whole surface in one pass and rewrites its rows in bulk (TakeWholeSurface,
  // Write). Why half: past it, the rows the local path deletes and inserts one statement each
  // (R twice, ~3 us a row, plus the links across R's outline and a re-triangulation of the
  // growing R per round until its outline is Delaunay, three rounds for a whole map) cost more
  // than deleting every triangle row in one statement and inserting all of them 64 to a statement
  // (~1 us a row) after a single re-triangulation; and most triangle ids change either way (the
  // tests of local edits demand that less than half of them do). Regions under
  // kMinWholeSurfaceRegion triangles stay local without counting the surface.
  Result<bool> RegionIsMostOfTheSurface() {
    if (region_.size() < kMinWholeSurfaceRegion) return false;
    TB_ASSIGN_OR_RETURN(const int64_t triangles, SurfaceTriangles());
    return static_cast<int64_t>(region_.size()) * 2 > triangles;
  }

  // R becomes every triangle of the surface: its outline is then the domain boundary, with no
  // triangle across, so one re-triangulation settles it, and no stored triangle is left to
  // repaint (the paint of every new triangle is computed in Write).
  Status TakeWholeSurface() {
    if (surface_ids_.empty()) {
      TB_ASSIGN_OR_RETURN(surface_ids_, mesh_.LoadSurface());
      result_.read_whole_surface = true;
    }
    for (int64_t t : surface_ids_) AddToRegion(t);
    paint_box_ = edit_.changed;
    return Status::Ok();
  }

  void AddToRegion(int64_t t) {
    if (region_.insert(t).second) order_.push_back(t);
  }

  // The triangles across R's failed outline edges join R with two rings of their neighbours:
  // the outline then moves three triangles out, where the new triangulation seldom reaches, so R
  // settles in fewer rounds (each re-triangulates all of R: a whole map in one edit took five
  // with none, and with one ring seven of the eight edits of the bands map whose R passed 1000
  // triangles still failed once more, at a neighbour; with two, one does).
  Status GrowAround(const std::vector<int64_t>& failed) {
    std::vector<int64_t> ring = failed;
    for (int depth = 0; depth < 2; ++depth) {
      std::vector<int64_t> next;
      for (int64_t t : ring) {
        AddToRegion(t);
        TB_ASSIGN_OR_RETURN(const MeshTriangle* tri, mesh_.Triangle(t));
        const MeshTriangle here = *tri;
        for (const std::optional<int64_t>& n : here.n)
          if (n && !region_.count(*n)) next.push_back(*n);
      }
      ring = std::move(next);
    }
    for (int64_t t : ring) AddToRegion(t);
    return Status::Ok();
  }

  // `what` names the point in the error (called only then: it is built for every ring point).
  template <typename Describe>
  Result<int64_t> Locate(const Point2& p, const Describe& what) {
    auto located = locator_.LocateTriangle(p.x, p.y);
    if (located.ok()) return located->triangle;
    if (located.status().code() == StatusCode::kNotFound)
      return Status::InvalidArgument(what() + ": " + FormatPoint(p) + " lies outside surface '" +
                                     surface_.name + "'");
    return located.status();
  }

  // The constraints of removed features go; the stars of their vertices join R, and ring or
  // Steiner vertices left on no constraint are dropped. A removed replace feature's inside joins
  // R too: its vertices get their DEM z back and its cells must meet the tolerance again.
  Status SeedRemovals() {
    const std::set<int64_t> removing(edit_.remove.begin(), edit_.remove.end());
    std::set<int64_t> touched;
    for (int64_t feature : edit_.remove) {
      TB_ASSIGN_OR_RETURN(std::vector<Edge> edges, mesh_.EdgesOf(feature));
      for (const Edge& e : edges) {
        TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* owners, mesh_.Owners(e.first, e.second));
        const bool gone = std::all_of(owners->begin(), owners->end(),
                                      [&](int64_t f) { return removing.count(f) > 0; });
        if (gone) removed_edges_.insert(e);
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
      for (int64_t t : star) AddToRegion(t);
      if (!closed || (vertex->kind != VertexKind::kRing && vertex->kind != VertexKind::kSteiner))
        continue;
      bool still_constrained = false;
      for (int64_t t : star) {
        TB_ASSIGN_OR_RETURN(const MeshTriangle* tri, mesh_.Triangle(t));
        for (int64_t w : tri->v) {
          if (w == v || removed_edges_.count(Key(v, w))) continue;
          TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* owners, mesh_.Owners(v, w));
          if (!owners->empty()) still_constrained = true;
        }
      }
      if (!still_constrained) dropped_.insert(v);
    }
    return SeedRemovedReplaceInsides();
  }

  Status SeedRemovedReplaceInsides() {
    std::vector<Polygon> polygons;
    Box box;
    for (int64_t id : edit_.remove) {
      auto f = LoadFeature(store_, surface_, id);  // REQUIRES of Apply: the row still exists
      if (!f.ok()) return f.status();
      removed_features_.push_back(std::move(*f));
      const EditorFeature& removed = removed_features_.back();
      if (removed.mode != FeatureMode::kReplace) continue;
      polygons.insert(polygons.end(), removed.polygons.begin(), removed.polygons.end());
      box.Add(BoxOf(removed));
    }
    if (polygons.empty()) return Status::Ok();
    restore_ = std::make_unique<PolygonLocator>(polygons);
    TB_ASSIGN_OR_RETURN(std::vector<int64_t> candidates, mesh_.TrianglesInBox(box));
    for (int64_t t : candidates) {
      TB_ASSIGN_OR_RETURN(const MeshTriangle* tri, mesh_.Triangle(t));
      Point2 centroid{0, 0};
      for (int64_t v : tri->v) {
        TB_ASSIGN_OR_RETURN(Point2 p, mesh_.At(v));
        centroid.x += p.x / 3, centroid.y += p.y / 3;
      }
      if (restore_->Locate(centroid) != PointInPolygon::kOutside) AddToRegion(t);
    }
    return Status::Ok();
  }

  // Moves each new point within the snap distance of an existing vertex (of the triangle holding
  // it) or of an earlier new point onto it, so near-duplicates (rings of neighbouring features
  // digitised or reprojected apart by round-off) become one vertex instead of a sliver.
  Status SnapPoints() {
    const double snap =
        kSnapCells * std::max(dem_.geometry.cell_x, std::fabs(dem_.geometry.cell_y));
    std::unordered_map<std::pair<int64_t, int64_t>, std::vector<Point2>, EdgeHash> buckets;
    const auto bucket = [snap](double v) { return static_cast<int64_t>(std::floor(v / snap)); };
    for (EditPolyline& line : lines_) {
      located_.emplace_back();
      snapped_to_.emplace_back();
      std::optional<int64_t> previous;  // the triangle holding the previous point
      for (size_t i = 0; i < line.points.size(); ++i) {
        TinVertex& p = line.points[i];
        const auto what = [&line, i] {
          return "feature " + std::to_string(line.feature) + ", point " + std::to_string(i);
        };
        // Draped ring points lie a DEM cell or less apart, often several in one triangle; a
        // point strictly inside the previous point's triangle lies in no other, so the locator
        // would return that triangle: no walk.
        bool same = false;
        if (previous) {
          TB_ASSIGN_OR_RETURN(same, StrictlyInside(*previous, {p.x, p.y}));
        }
        int64_t t = previous.value_or(0);
        if (!same) {
          TB_ASSIGN_OR_RETURN(t, Locate({p.x, p.y}, what));
        }
        TB_ASSIGN_OR_RETURN(const MeshTriangle* tri, mesh_.Triangle(t));
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
          TB_ASSIGN_OR_RETURN(snapped, SnapOntoConstraint(t, snap, p));
        }
        buckets[{bx, by}].push_back({p.x, p.y});
        located_.back().push_back(t);
        snapped_to_.back().push_back(vertex);
        previous = t;
      }
    }
    return Status::Ok();
  }

  // Moves `p` onto a kept constrained edge closer than `snap` (of triangle `t` or a neighbour, not
  // near its ends, not on the domain boundary) and records that the edge is to be split there:
  // left where it was, p would sit a hair beside the edge and make a sliver (or a crossing a
  // hair away from it). Both triangles of the edge join R, so the split stays inside it. The
  // projection lies on the edge only up to round-off, which the writer's walk along split
  // constraints allows for.
  Result<bool> SnapOntoConstraint(int64_t t, double snap, TinVertex& p) {
    TB_ASSIGN_OR_RETURN(const MeshTriangle* holding, mesh_.Triangle(t));
    std::vector<int64_t> candidates{t};
    for (const std::optional<int64_t>& n : holding->n)
      if (n) candidates.push_back(*n);
    for (int64_t c : candidates) {
      TB_ASSIGN_OR_RETURN(const MeshTriangle* tri, mesh_.Triangle(c));
      const MeshTriangle here = *tri;
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
        const double ends = snap / len;
        if (along <= ends || along >= 1 - ends || off > snap) continue;
        if (removed_edges_.count(Key(a, b))) continue;
        TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* owners, mesh_.Owners(a, b));
        if (owners->empty()) continue;
        p.x = pa.x + along * dx, p.y = pa.y + along * dy;
        splits_[Key(a, b)].push_back({a < b ? along : 1 - along, Point2{p.x, p.y}});
        AddToRegion(c);
        AddToRegion(*here.n[i]);
        return true;
      }
    }
    return false;
  }

  // A new segment whose ends snapped onto the two ends of a kept constrained edge runs exactly
  // along it: the shared boundary of neighbouring polygons, half the segments of a map layer
  // loaded feature by feature. Constraining an edge that already is one leaves the CDT as it is,
  // so such a segment seeds no conflict region; it only gains an owner (present_), whose row
  // Write adds, piece by piece if R's re-triangulation splits the edge. The rest of its line
  // goes on as open chains of the other segments. Off while the surface has replace features
  // or the edit removes any: both change vertex z, which only R and the paint area settle.
  Status SetAsidePresentSegments() {
    if (!replace_polygons_.empty() || !edit_.remove.empty()) return Status::Ok();
    std::vector<EditPolyline> chains;
    std::vector<std::vector<int64_t>> chains_located;
    for (size_t l = 0; l < lines_.size(); ++l) {
      const EditPolyline& line = lines_[l];
      const size_t n = line.points.size();
      const size_t segments = line.closed ? n : (n > 0 ? n - 1 : 0);
      std::vector<uint8_t> present(segments, 0);
      for (size_t i = 0; i < segments; ++i) {
        TB_ASSIGN_OR_RETURN(const bool along, RunsAlongAConstraint(l, i, (i + 1) % n));
        present[i] = along;
      }
      const auto first_present = std::find(present.begin(), present.end(), uint8_t{1});
      if (first_present == present.end()) {
        chains.push_back(std::move(lines_[l]));
        chains_located.push_back(std::move(located_[l]));
        continue;
      }
      // A closed line's chains start after a present segment, so none wraps around.
      const size_t start =
          line.closed ? static_cast<size_t>(first_present - present.begin()) + 1 : 0;
      EditPolyline chain{{}, false, line.feature};
      std::vector<int64_t> chain_located;
      const auto end_chain = [&] {
        if (!chain.points.empty()) {
          chains.push_back(std::move(chain));
          chains_located.push_back(std::move(chain_located));
        }
        chain = EditPolyline{{}, false, line.feature};
        chain_located.clear();
      };
      for (size_t k = 0; k < segments; ++k) {
        const size_t i = (start + k) % segments, j = (i + 1) % n;
        if (present[i]) {
          const int64_t a = snapped_to_[l][i], b = snapped_to_[l][j];
          if (a != b) present_[Key(a, b)].push_back(line.feature);
          end_chain();
          continue;
        }
        if (chain.points.empty()) {
          chain.points.push_back(line.points[i]);
          chain_located.push_back(located_[l][i]);
        }
        chain.points.push_back(line.points[j]);
        chain_located.push_back(located_[l][j]);
      }
      end_chain();
    }
    lines_ = std::move(chains);
    located_ = std::move(chains_located);
    snapped_to_.clear();  // no longer matches lines_
    return Status::Ok();
  }

  // Whether the segment from point i to point j of line l lies on a kept constrained edge: both
  // ends snapped onto its vertices (or onto one vertex: a segment of length 0), and no point of
  // this edit splits it.
  Result<bool> RunsAlongAConstraint(size_t l, size_t i, size_t j) {
    const int64_t a = snapped_to_[l][i], b = snapped_to_[l][j];
    if (a == 0 || b == 0) return false;
    if (a == b) return true;
    const Edge e = Key(a, b);
    if (removed_edges_.count(e) || splits_.count(e) || dropped_.count(a) || dropped_.count(b))
      return false;
    TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* owners, mesh_.Owners(a, b));
    return !owners->empty();
  }

  // Every triangle a new segment touches (closed: a segment through a vertex takes its fan),
  // found by a walk over neighbours from the triangle holding the segment's first point.
  // Existing vertices closer than the snap distance to a new segment (but not its ends) become
  // points of it: a crossing vertex an earlier edit constructed lies only nearly on the line, and
  // CGAL would otherwise reroute the constraint through another vertex (CGAL#6602).
  Status SeedPolylines() {
    const double snap =
        kSnapCells * std::max(dem_.geometry.cell_x, std::fabs(dem_.geometry.cell_y));
    for (size_t l = 0; l < lines_.size(); ++l) {
      EditPolyline& line = lines_[l];
      const size_t n = line.points.size();
      const size_t segments = line.closed ? n : n - 1;
      std::vector<TinVertex> points;
      for (size_t i = 0; i < n; ++i) {
        const Point2 p{line.points[i].x, line.points[i].y};
        points.push_back(line.points[i]);
        new_points_.push_back(p);
        if (i >= segments) continue;
        const Point2 q{line.points[(i + 1) % n].x, line.points[(i + 1) % n].y};
        const int64_t start = located_[l][i];  // SnapPoints located every point
        std::vector<int64_t> queue{start};
        std::unordered_set<int64_t> seen{start};
        std::map<double, TinVertex> on_segment;  // by position along pq
        const double dx = q.x - p.x, dy = q.y - p.y, len2 = dx * dx + dy * dy;
        while (!queue.empty()) {
          const int64_t t = queue.back();
          queue.pop_back();
          AddToRegion(t);
          TB_ASSIGN_OR_RETURN(const MeshTriangle* tri, mesh_.Triangle(t));
          for (int64_t v : tri->v) {
            TB_ASSIGN_OR_RETURN(const TinVertex* w, mesh_.Vertex(v));
            if (len2 == 0) break;
            const double along = ((w->x - p.x) * dx + (w->y - p.y) * dy) / len2;
            const double off = std::fabs((w->x - p.x) * dy - (w->y - p.y) * dx) / std::sqrt(len2);
            const double ends = snap / std::sqrt(len2);
            if (along > ends && along < 1 - ends && off <= snap) on_segment.emplace(along, *w);
          }
          for (const std::optional<int64_t>& next : tri->n) {
            if (!next || !seen.insert(*next).second) continue;
            TB_ASSIGN_OR_RETURN(bool meets, Meets(*next, p, q));
            if (meets) queue.push_back(*next);
          }
        }
        for (const auto& [along, w] : on_segment) {
          points.push_back(w);
          new_points_.push_back({w.x, w.y});
        }
      }
      line.points = std::move(points);
    }
    return Status::Ok();
  }

  Result<bool> Meets(int64_t t, const Point2& p, const Point2& q) {
    TB_ASSIGN_OR_RETURN(Corners3 c, Corners(t));
    return SegmentMeetsTriangle(p, q, c[0], c[1], c[2]);
  }

  // True when `p` lies inside stored triangle `t`, off its edges (exact).
  Result<bool> StrictlyInside(int64_t t, const Point2& p) {
    TB_ASSIGN_OR_RETURN(Corners3 c, Corners(t));
    return Orientation(c[0], c[1], p) > 0 && Orientation(c[1], c[2], p) > 0 &&
           Orientation(c[2], c[0], p) > 0;
  }

  Result<Corners3> Corners(int64_t t) {
    TB_ASSIGN_OR_RETURN(const MeshTriangle* tri, mesh_.Triangle(t));
    Corners3 c;
    for (int i = 0; i < 3; ++i) {
      TB_ASSIGN_OR_RETURN(c[i], mesh_.At(tri->v[i]));
    }
    return c;
  }

  // Grows R across unconstrained outline edges by the triangles whose circumcircle strictly
  // holds a new point (the Bowyer-Watson cavity): they cannot survive the insertion. Later
  // rounds catch anything this misses (refinement points), so this only saves rounds.
  Status GrowByCircumcircles() {
    if (new_points_.empty()) return Status::Ok();
    std::vector<Point2> points = new_points_;
    std::sort(points.begin(), points.end(),
              [](const Point2& a, const Point2& b) { return a.x < b.x; });
    for (size_t k = 0; k < order_.size(); ++k) {
      const int64_t t = order_[k];
      TB_ASSIGN_OR_RETURN(const MeshTriangle* tri, mesh_.Triangle(t));
      const MeshTriangle here = *tri;
      for (int i = 0; i < 3; ++i) {
        if (!here.n[i] || region_.count(*here.n[i])) continue;
        const int64_t a = here.v[(i + 1) % 3], b = here.v[(i + 2) % 3];
        TB_ASSIGN_OR_RETURN(auto c, Corners(*here.n[i]));
        if (!CircleHoldsAny(c, points)) continue;
        // A kept constraint shields the triangle across (checked second: it reads a row).
        TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* owners, mesh_.Owners(a, b));
        if (!owners->empty() && !removed_edges_.count(Key(a, b))) continue;
        AddToRegion(*here.n[i]);
      }
    }
    return Status::Ok();
  }

  static bool CircleHoldsAny(const Corners3& c, const std::vector<Point2>& sorted) {
    // Circumcentre and radius in doubles only bound the candidates; InCircle decides exactly.
    const double ax = c[0].x, ay = c[0].y;
    const double bx = c[1].x - ax, by = c[1].y - ay, cx = c[2].x - ax, cy = c[2].y - ay;
    const double d = 2 * (bx * cy - by * cx);
    double lo = -std::numeric_limits<double>::infinity(), hi = -lo;
    if (d != 0) {
      const double ux = (cy * (bx * bx + by * by) - by * (cx * cx + cy * cy)) / d;
      const double uy = (bx * (cx * cx + cy * cy) - cx * (bx * bx + by * by)) / d;
      const double r = std::hypot(ux, uy) * (1 + 1e-9) + 1e-9;
      lo = ax + ux - r, hi = ax + ux + r;
    }
    auto it = std::lower_bound(sorted.begin(), sorted.end(), lo,
                               [](const Point2& p, double x) { return p.x < x; });
    for (; it != sorted.end() && it->x <= hi; ++it)
      if (InCircle(c[0], c[1], c[2], *it) > 0) return true;
    return false;
  }

  // Where the paint of stored triangles may change, block by block (centroid blocks,
  // core/tin/ring_blocks.h) over the changed features' box. Paint is a function of the features
  // holding a triangle's centroid (and of nodata), so a block no changed ring comes near and
  // whose centre no changed polygon holds keeps its paint and is skipped (a clip feature changes
  // paint everywhere: skipping is off). A block no ring of any feature comes near, over DEM data
  // only, takes one paint for all its triangles: it is repainted by one statement in Write
  // without being read. The rest ("mixed" blocks) are read and painted triangle by triangle, as
  // are all blocks when a changed feature sets vertex z (replace), since z is per vertex.
  Status FindPaintArea() {
    if (edit_.changed.empty()) return Status::Ok();
    const BlockGrid& g = surface_.blocks;
    const BlockWindow window{g.ColumnOf(edit_.changed.min_x), g.RowOf(edit_.changed.min_y),
                             g.ColumnOf(edit_.changed.max_x), g.RowOf(edit_.changed.max_y)};
    std::set<int64_t> added_ids;
    for (const EditPolyline& line : edit_.add) added_ids.insert(line.feature);
    std::vector<Polygon> changed;
    bool anywhere = false, per_triangle = false;
    RingBlocks near_any(g, window), near_changed(g, window);
    Box window_box;  // the window's blocks, grown by the margin RingBlocks tests them with
    const double reach = g.size / 2 + RingBlocks::kMargin * g.size;
    const Point2 low = near_any.Centre(window.bx0, window.by0);
    const Point2 high = near_any.Centre(window.bx1, window.by1);
    window_box.Add(Point2{low.x - reach, low.y - reach});
    window_box.Add(Point2{high.x + reach, high.y + reach});
    const auto note = [&](const EditorFeature& f, bool is_changed) {
      if (!is_changed && !BoxOf(f).Meets(window_box)) return;  // no ring of it near the window
      if (f.mode == FeatureMode::kBreakline) return;
      near_any.AddBlocks(RingBlocksOf(f, g));
      if (!is_changed) return;
      near_changed.AddBlocks(RingBlocksOf(f, g));
      changed.insert(changed.end(), f.polygons.begin(), f.polygons.end());
      anywhere |= f.mode == FeatureMode::kClip;
      per_triangle |= f.mode == FeatureMode::kReplace;
    };
    for (const EditorFeature& f : edit_.features) note(f, added_ids.count(f.id) > 0);
    for (const EditorFeature& f : removed_features_) note(f, true);
    changed_inside_ = std::make_unique<PolygonLocator>(changed);
    const PolygonLocator& inside_changed = *changed_inside_;
    // A stored triangle outside R lies wholly on one side of every changed ring, so one outside
    // the changed features keeps its paint: Write need not paint it. Not so for clip (outside
    // changes too) or replace (z changes at the ring's vertices, found through the triangles).
    outside_keeps_paint_ = !anywhere && !per_triangle;

    // The DEM under the window, for the data test of whole blocks; read only if one may be.
    std::optional<Grid> window_dem;
    const auto on_data = [&](const Point2& c) -> Result<bool> {
      if (!window_dem) {
        const double cell = std::max(dem_.geometry.cell_x, std::fabs(dem_.geometry.cell_y));
        TB_ASSIGN_OR_RETURN(
            window_dem, dems_.ReadWindow(dem_, {low.x - g.size - cell, low.y - g.size - cell,
                                                high.x + g.size + cell, high.y + g.size + cell}));
      }
      return BoxOnData(*window_dem, c.x - reach, c.y - reach, c.x + reach, c.y + reach);
    };
    Tin centres;  // one point-like triangle per uniform block, at its centre
    Box mixed_box;
    for (int64_t by = window.by0; by <= window.by1; ++by) {
      int64_t run = -1;  // first block of the current run of mixed blocks in this row
      for (int64_t bx = window.bx0; bx <= window.bx1 + 1; ++bx) {
        bool mixed = false;
        if (bx <= window.bx1) {
          const Point2 c = near_any.Centre(bx, by);
          const bool may_change = anywhere || near_changed.Near(bx, by) ||
                                  inside_changed.Locate(c) != PointInPolygon::kOutside;
          bool uniform = may_change && !per_triangle && !near_any.Near(bx, by);
          if (uniform) {
            TB_ASSIGN_OR_RETURN(uniform, on_data(c));
          }
          if (uniform) {
            uniform_blocks_.push_back(BlockGrid::Pack(bx, by));
            const uint32_t v = static_cast<uint32_t>(centres.vertices.size());
            centres.vertices.push_back({c.x, c.y, 0});
            centres.triangles.push_back(TinTriangle{{v, v, v}});
          } else {
            mixed = may_change;
          }
        }
        if (mixed && run < 0) run = bx;
        if (!mixed && run >= 0) {
          TB_RETURN_IF_ERROR(mesh_.TrianglesInBlocks(by, run, bx - 1, &around_));
          // The paint of these triangles reads the DEM at their centroids, which lie in these
          // blocks.
          mixed_box.Add(Point2{g.origin_x + static_cast<double>(run) * g.size,
                               g.origin_y + static_cast<double>(by) * g.size});
          mixed_box.Add(Point2{g.origin_x + static_cast<double>(bx) * g.size,
                               g.origin_y + static_cast<double>(by + 1) * g.size});
          run = -1;
        }
      }
    }
    if (!uniform_blocks_.empty()) {
      uniform_paint_ =
          PaintFromFeatures(edit_.features, static_cast<const Grid*>(nullptr), centres);
      uniform_tags_ = std::move(centres.tags);
    }
    paint_box_ = edit_.changed;
    paint_box_.Add(mixed_box);
    return Status::Ok();
  }

  // --- re-triangulating R -------------------------------------------------------------------

  // z of an existing vertex after the edit: a replace level, the DEM again where a removed
  // replace feature had flattened it, else as stored.
  double TargetZ(const TinVertex& v) {
    if (auto level = levels_.At({v.x, v.y})) return *level;
    if (restore_ && restore_->Locate({v.x, v.y}) != PointInPolygon::kOutside) {
      const double z = DemZ(v.x, v.y);
      if (std::isfinite(z)) return z;
    }
    return v.z;
  }

  double DemZ(double x, double y) {
    auto z = dems_.Sample(dem_, x, y);
    return z.ok() ? *z : std::numeric_limits<double>::quiet_NaN();
  }

  // z of a point the edit creates (ring points, crossings): the replace level or the DEM.
  double NewZ(double x, double y) {
    if (auto level = levels_.At({x, y})) return *level;
    return DemZ(x, y);
  }

  Result<LocalPatch> Retriangulate() {
    LocalPatch patch;
    outline_.clear();
    std::vector<TinVertex> points;
    std::unordered_map<int64_t, uint32_t> local;  // store id -> local index
    local.reserve(order_.size() * 2);
    std::vector<Corners3> region_triangles;
    std::vector<std::pair<Point2, Point2>> outline_segments;
    Box box = paint_box_;
    for (int64_t t : order_) {
      TB_ASSIGN_OR_RETURN(const MeshTriangle* tri, mesh_.Triangle(t));
      Corners3 corners;
      for (int i = 0; i < 3; ++i) {
        const int64_t id = tri->v[i];
        TB_ASSIGN_OR_RETURN(const TinVertex* v, mesh_.Vertex(id));
        corners[i] = {v->x, v->y};
        box.Add(corners[i]);
        if (dropped_.count(id) || local.count(id)) continue;
        local.emplace(id, static_cast<uint32_t>(points.size()));
        TinVertex copy = *v;
        copy.z = TargetZ(*v);
        points.push_back(copy);
        patch.store_ids.push_back(id);
      }
      region_triangles.push_back(corners);
      for (int i = 0; i < 3; ++i) {
        const std::optional<int64_t>& n = tri->n[i];
        if (!n || !region_.count(*n)) {
          outline_.push_back({tri->v[(i + 1) % 3], tri->v[(i + 2) % 3], n});
          outline_segments.push_back({corners[(i + 1) % 3], corners[(i + 2) % 3]});
        }
      }
    }
    outline_index_.Build(std::move(outline_segments));
    for (const Corners3& c : region_triangles)
      for (const Point2& p : c) result_.region.Add(p);
    const double cell = std::max(dem_.geometry.cell_x, std::fabs(dem_.geometry.cell_y));
    TB_ASSIGN_OR_RETURN(grid_,
                        dems_.ReadWindow(dem_, {box.min_x - 2 * cell, box.min_y - 2 * cell,
                                                box.max_x + 2 * cell, box.max_y + 2 * cell}));
    if (order_.empty()) return patch;  // nothing to re-triangulate: a paint-only edit

    Cdt cdt;
    cdt.InsertVertices(points);  // distinct store vertices: local index i is points[i]
    for (const EditPolyline& line : lines_) {
      std::vector<TinVertex> draped = line.points;
      for (TinVertex& p : draped) {
        p.kind = VertexKind::kRing;
        if (auto level = levels_.At({p.x, p.y})) p.z = *level;
      }
      patch.lines.push_back(cdt.InsertVertices(draped));
    }
    if (!carried_.empty()) cdt.InsertVertices(carried_);
    for (const OutlineEdge& e : outline_) cdt.InsertConstraint(local.at(e.a), local.at(e.b));
    const std::set<int64_t> removing(edit_.remove.begin(), edit_.remove.end());
    for (int64_t t : order_) {
      TB_ASSIGN_OR_RETURN(const MeshTriangle* tri, mesh_.Triangle(t));
      for (int i = 0; i < 3; ++i) {
        // An edge between two triangles of R is taken from the one with the smaller id.
        const std::optional<int64_t>& across = tri->n[(i + 2) % 3];
        if (across && *across < t && region_.count(*across)) continue;
        const Edge e = Key(tri->v[i], tri->v[(i + 1) % 3]);
        if (removed_edges_.count(e)) continue;
        TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* owners, mesh_.Owners(e.first, e.second));
        if (owners->empty()) continue;
        std::vector<int64_t> kept;
        for (int64_t f : *owners)
          if (!removing.count(f)) kept.push_back(f);
        InsertSplitConstraint(cdt, e, local, patch);
        patch.old_constraints.push_back({e, kept});
      }
    }
    for (size_t l = 0; l < lines_.size(); ++l) {
      const std::vector<uint32_t>& idx = patch.lines[l];
      const size_t n = idx.size();
      const size_t segments = lines_[l].closed ? n : n - 1;
      for (size_t i = 0; i < segments; ++i)
        if (idx[i] != idx[(i + 1) % n]) cdt.InsertConstraint(idx[i], idx[(i + 1) % n]);
    }
    const ElevationFn elevation = [this](double x, double y) { return NewZ(x, y); };
    cdt.IndexCrossings(elevation);

    std::vector<std::pair<uint32_t, uint32_t>> outline_edges;
    for (const OutlineEdge& e : outline_) outline_edges.push_back({local.at(e.a), local.at(e.b)});
    const DirectedOutline outline_local(points.size(), outline_edges);

    // Refinement inside R only: the faces ClassifyInside finds now, and the faces refinement
    // creates (each has a new vertex). A cell centre exactly on the outline is left alone: it
    // would split an outline edge, and the triangle across already meets the tolerance there
    // (both interpolate the same edge).
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
    refine.tolerance = surface_.tolerance.value_or(1.0);
    refine.excluded = [this](double x, double y) {
      if (outline_index_.OnAny({x, y})) return true;
      return !replace_polygons_.empty() && replaced_->Locate({x, y}) != PointInPolygon::kOutside;
    };
    if (!every_face_inside) {
      refine.in_region = [&](const std::array<uint32_t, 3>& v) {
        if (v[0] >= before || v[1] >= before || v[2] >= before) return true;
        std::array<uint32_t, 3> key = v;
        std::sort(key.begin(), key.end());
        return std::binary_search(inside_faces.begin(), inside_faces.end(), key);
      };
    }
    RefineToTolerance(cdt, grid_, refine);
    for (size_t i = before; i < cdt.vertices().size(); ++i) carried_.push_back(cdt.vertices()[i]);
    patch.refinement_points = static_cast<int64_t>(carried_.size());

    // Refinement only inserts points: with none inserted the triangulation is the one classified.
    const bool refined = cdt.vertices().size() != before;
    patch.tin = refined ? cdt.ToTin(elevation) : std::move(now);
    patch.store_ids.resize(patch.tin.vertices.size(), 0);
    // Refinement adds points inside the faces it scans, so a triangulation that was all R stays so.
    if (every_face_inside)
      patch.inside.assign(patch.tin.triangles.size(), 1);
    else
      patch.inside = refined ? ClassifyInside(patch.tin, outline_local) : std::move(inside);
    local_ = std::move(local);
    return patch;
  }

  // Kept constraint e, through the new points snapped onto it (SnapOntoConstraint) in order.
  void InsertSplitConstraint(Cdt& cdt, const Edge& e,
                             const std::unordered_map<int64_t, uint32_t>& local,
                             const LocalPatch& patch) {
    std::vector<uint32_t> chain{local.at(e.first)};
    if (auto it = splits_.find(e); it != splits_.end()) {
      std::vector<std::pair<double, Point2>> points = it->second;
      std::sort(points.begin(), points.end(),
                [](const auto& l, const auto& r) { return l.first < r.first; });
      for (const auto& [along, p] : points)
        if (auto index = LocalIndexOfNewPoint(p, patch)) chain.push_back(*index);
    }
    chain.push_back(local.at(e.second));
    for (size_t i = 0; i + 1 < chain.size(); ++i)
      if (chain[i] != chain[i + 1]) cdt.InsertConstraint(chain[i], chain[i + 1]);
  }

  // The local index of the polyline point at exactly `p`, if any.
  std::optional<uint32_t> LocalIndexOfNewPoint(const Point2& p, const LocalPatch& patch) const {
    for (size_t l = 0; l < lines_.size(); ++l)
      for (size_t i = 0; i < lines_[l].points.size(); ++i)
        if (lines_[l].points[i].x == p.x && lines_[l].points[i].y == p.y) return patch.lines[l][i];
    return std::nullopt;
  }

  // The outer triangles that must join R: across an outline edge that the patch no longer has
  // (a point split it) or that is not locally Delaunay (and not a kept constraint).
  Result<std::vector<int64_t>> CheckOutline(const LocalPatch& patch) {
    std::vector<int64_t> grow;
    const auto has_outer = [](const OutlineEdge& e) { return e.outer.has_value(); };
    if (std::none_of(outline_.begin(), outline_.end(), has_outer)) return grow;
    std::unordered_map<Edge, uint32_t, EdgeHash> directed;  // local (a, b) -> inside triangle
    for (size_t t = 0; t < patch.tin.triangles.size(); ++t) {
      if (!patch.inside[t]) continue;
      const auto& v = patch.tin.triangles[t].v;
      for (int i = 0; i < 3; ++i) directed.emplace(Edge{v[i], v[(i + 1) % 3]}, t);
    }
    for (const OutlineEdge& e : outline_) {
      if (!e.outer) continue;
      const uint32_t a = local_.at(e.a), b = local_.at(e.b);
      auto it = directed.find(Edge{a, b});
      if (it == directed.end()) {
        grow.push_back(*e.outer);
        continue;
      }
      TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* owners, mesh_.Owners(e.a, e.b));
      if (!owners->empty() && !removed_edges_.count(Key(e.a, e.b))) continue;
      TB_ASSIGN_OR_RETURN(const MeshTriangle* outer, mesh_.Triangle(*e.outer));
      int64_t far = outer->v[0];
      for (int64_t w : outer->v)
        if (w != e.a && w != e.b) far = w;
      TB_ASSIGN_OR_RETURN(Point2 fp, mesh_.At(far));
      const TinTriangle& inner = patch.tin.triangles[it->second];
      const auto& p = patch.tin.vertices;
      if (InCircle({p[inner.v[0]].x, p[inner.v[0]].y}, {p[inner.v[1]].x, p[inner.v[1]].y},
                   {p[inner.v[2]].x, p[inner.v[2]].y}, fp) > 0)
        grow.push_back(*e.outer);
    }
    return grow;
  }

  // --- writing ------------------------------------------------------------------------------

  // Foreign keys unchecked (db/sqlite/unchecked_foreign_keys.h) while the result lives, for the
  // bulk statements of a whole-surface edit, whose keys the caller has made sure of. A local
  // edit keeps them checked: turning enforcement off and on again expires every prepared
  // statement of the connection (sqlite3_db_config), and with them unchecked in every edit a
  // load feature by feature (`--each`) measured ~15% more CPU than before instead of less.
  Result<std::optional<UncheckedForeignKeys>> UncheckedIfWholeSurface() {
    if (!whole_surface_) return std::optional<UncheckedForeignKeys>();
    TB_ASSIGN_OR_RETURN(UncheckedForeignKeys unchecked, UncheckedForeignKeys::Begin(store_.db()));
    return std::optional<UncheckedForeignKeys>(std::move(unchecked));
  }

  Status Step() {
    ++step_;
    return hook_ ? hook_(step_) : Status::Ok();
  }

  // The constrained sub-edges of the patch from local vertex a to b: a walk along constrained
  // edges that advances along ab and stays on it (a crossing or a point on the segment splits
  // it). Crossing points are constructed inexactly, so "on it" allows 1e-7 of its length; among
  // the candidates the one nearest the line wins, so a crossing constraint is never followed.
  static Result<std::vector<std::pair<uint32_t, uint32_t>>> Pieces(
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

  Status Write(const LocalPatch& patch) {
    SqliteDb& db = store_.db();
    const Tin& tin = patch.tin;
    if (!page_cache_ || !page_cache_->raised()) {
      // Rows deleted, inserted and repainted; a uniform block holds about the builders' number.
      const auto inserted =
          static_cast<size_t>(std::count(patch.inside.begin(), patch.inside.end(), uint8_t{1}));
      const size_t rows = order_.size() + inserted + around_.size() +
                          uniform_blocks_.size() * BlockGrid::kDefaultPerBlock;
      page_cache_ = std::make_unique<ScopedPageCache>(db, rows);
    }
    std::vector<int64_t> ids = patch.store_ids;
    int64_t first_new_vertex = 0, end_new_vertex = 0;  // the new vertices' ids, [first, end)
    {
      std::vector<uint8_t> used(tin.vertices.size(), 0);
      for (size_t t = 0; t < tin.triangles.size(); ++t)
        if (patch.inside[t])
          for (uint32_t v : tin.triangles[t].v) used[v] = 1;
      for (size_t i = 0; i < tin.vertices.size(); ++i)
        if (ids[i] == 0 && !used[i])
          return Status::Corruption("surface '" + surface_.name + "': the new vertex at " +
                                    FormatPoint({tin.vertices[i].x, tin.vertices[i].y}) +
                                    " fell outside the conflict region (kind " +
                                    VertexKindName(tin.vertices[i].kind) + ", round " +
                                    std::to_string(result_.rounds) + ")");
    }

    // New vertices (ring points, crossings, refinement points) and z of replaced vertices.
    TB_RETURN_IF_ERROR(Step());
    {
      // Local indices of the new vertices, in id order.
      std::vector<uint32_t> fresh;
      for (size_t i = 0; i < tin.vertices.size(); ++i) {
        if (ids[i] != 0) continue;
        const TinVertex& v = tin.vertices[i];
        if (!std::isfinite(v.z))
          return Status::InvalidArgument("no elevation for the new vertex at " +
                                         FormatPoint({v.x, v.y}));
        fresh.push_back(static_cast<uint32_t>(i));
      }
      TB_ASSIGN_OR_RETURN(const int64_t first, NextId(db, "vertices"));
      first_new_vertex = first;
      end_new_vertex = first + static_cast<int64_t>(fresh.size());
      for (size_t k = 0; k < fresh.size(); ++k) {
        ids[fresh[k]] = first + static_cast<int64_t>(k);
        mesh_.PutVertex(ids[fresh[k]], tin.vertices[fresh[k]]);
      }
      TB_RETURN_IF_ERROR(InsertNumberedRows(db, "vertices(surface, x, y, z, kind)", 5, fresh.size(),
                                            first, [&](Statement& row, int p, size_t k) {
                                              const TinVertex& v = tin.vertices[fresh[k]];
                                              row.Bind(p, surface_.id).Bind(p + 1, v.x);
                                              row.Bind(p + 2, v.y).Bind(p + 3, v.z);
                                              row.BindStaticText(p + 4, VertexKindName(v.kind));
                                            }));
    }
    TB_RETURN_IF_ERROR(Step());
    TB_ASSIGN_OR_RETURN(Statement * set_z, db.Cached("UPDATE vertices SET z = ? WHERE id = ?"));
    for (size_t i = 0; i < tin.vertices.size(); ++i) {
      if (patch.store_ids[i] == 0) continue;
      TB_ASSIGN_OR_RETURN(const TinVertex* stored, mesh_.Vertex(patch.store_ids[i]));
      if (stored->z == tin.vertices[i].z) continue;
      TB_RETURN_IF_ERROR(set_z->Bind(1, tin.vertices[i].z).Bind(2, patch.store_ids[i]).Run());
      TinVertex moved = *stored;
      moved.z = tin.vertices[i].z;
      mesh_.PutVertex(patch.store_ids[i], moved);
    }

    // The patch's inside triangles get fresh ids above every id in the table, so an id never
    // comes back with another triangle: they are inserted before R's rows go, SQLite numbering
    // them on from the largest id (InsertNumberedRows). Their rows go in block order, as a built
    // surface's do, so that a later repaint of a block finds long runs of ids.
    TB_ASSIGN_OR_RETURN(const int64_t base, NextId(db, "triangles"));
    std::vector<uint32_t> written;  // the inside triangles in row order
    std::vector<int64_t> block(tin.triangles.size(), 0);
    {
      std::vector<std::pair<int64_t, uint32_t>> keyed;  // (block, local triangle)
      for (size_t t = 0; t < tin.triangles.size(); ++t) {
        if (!patch.inside[t]) continue;
        const auto& v = tin.triangles[t].v;
        const TinVertex &a = tin.vertices[v[0]], &b = tin.vertices[v[1]], &c = tin.vertices[v[2]];
        block[t] = CentroidBlock(surface_.blocks, a.x, a.y, b.x, b.y, c.x, c.y);
        keyed.push_back({block[t], static_cast<uint32_t>(t)});
      }
      std::sort(keyed.begin(), keyed.end());
      for (const auto& [b, t] : keyed) written.push_back(t);
    }
    std::vector<int64_t> new_id(tin.triangles.size(), 0);
    for (size_t k = 0; k < written.size(); ++k) new_id[written[k]] = base + static_cast<int64_t>(k);
    result_.added = static_cast<int64_t>(written.size());
    EdgeTable outer_across;  // store (a, b) of R's side -> the triangle across
    outer_across.Reserve(outline_.size());
    for (const OutlineEdge& e : outline_)
      if (e.outer) outer_across.Add(Edge{e.a, e.b}, *e.outer);
    outer_across.Seal();

    // Paint of the new triangles and of the stored ones around the changed features.
    Tin painted;
    std::unordered_map<int64_t, uint32_t> painted_vertex;
    painted_vertex.reserve(tin.vertices.size() + around_.size());
    const auto add_vertex = [&](int64_t id, const TinVertex& v) {
      auto [it, added] = painted_vertex.emplace(id, static_cast<uint32_t>(painted.vertices.size()));
      if (added) painted.vertices.push_back(v);
      return it->second;
    };
    for (uint32_t t : written) {
      TinTriangle tri;
      for (int i = 0; i < 3; ++i)
        tri.v[i] = add_vertex(ids[tin.triangles[t].v[i]], tin.vertices[tin.triangles[t].v[i]]);
      painted.triangles.push_back(tri);
    }
    std::vector<int64_t> kept_around;
    for (int64_t t : around_) {
      if (region_.count(t)) continue;
      TB_ASSIGN_OR_RETURN(const MeshTriangle* stored, mesh_.Triangle(t));
      std::array<const TinVertex*, 3> corner;
      for (int i = 0; i < 3; ++i) {
        TB_ASSIGN_OR_RETURN(corner[i], mesh_.Vertex(stored->v[i]));
      }
      if (outside_keeps_paint_) {
        const Point2 centroid{(corner[0]->x + corner[1]->x + corner[2]->x) / 3,
                              (corner[0]->y + corner[1]->y + corner[2]->y) / 3};
        if (changed_inside_->Locate(centroid) == PointInPolygon::kOutside) continue;
      }
      TinTriangle tri;
      for (int i = 0; i < 3; ++i) tri.v[i] = add_vertex(stored->v[i], *corner[i]);
      painted.triangles.push_back(tri);
      kept_around.push_back(t);
    }
    const Paint paint = PaintFromFeatures(edit_.features, &grid_, painted);
    std::vector<std::optional<int64_t>> tag_ids;
    for (const std::string& value : painted.tags) {
      TB_ASSIGN_OR_RETURN(int64_t id, InternTag(store_, value));
      tag_ids.push_back(id);
    }
    const auto tag_of = [&](size_t k) {
      return paint.tag[k] == kNoTag ? std::optional<int64_t>() : tag_ids[paint.tag[k]];
    };

    std::vector<MeshTriangle> rows(written.size());
    for (size_t k = 0; k < written.size(); ++k) {
      const TinTriangle& tri = tin.triangles[written[k]];
      MeshTriangle& row = rows[k];
      for (int i = 0; i < 3; ++i) {
        row.v[i] = ids[tri.v[i]];
        if (tri.n[i] != kNoNeighbour && patch.inside[tri.n[i]]) {
          row.n[i] = new_id[tri.n[i]];
        } else {
          const Edge across{ids[tri.v[(i + 1) % 3]], ids[tri.v[(i + 2) % 3]]};
          if (const int64_t* outer = outer_across.Find(across)) row.n[i] = *outer;
        }
      }
      row.visible = paint.visible[k] != 0;
      row.tag = tag_of(k);
      row.block = block[written[k]];
    }
    TB_RETURN_IF_ERROR(Step());
    {
      // Every key bound here holds: the surface is the one being edited, the tags were interned
      // above in this transaction.
      TB_ASSIGN_OR_RETURN(auto unchecked, UncheckedIfWholeSurface());
      TB_RETURN_IF_ERROR(InsertNumberedRows(
          db, "triangles(surface, v0, v1, v2, n0, n1, n2, visible, tag, block)", 10, written.size(),
          base, [&](Statement& row, int p, size_t k) { BindTriangleRow(row, p, rows[k]); }));
    }
    for (size_t k = 0; k < written.size(); ++k) {
      result_.visible_added += rows[k].visible;
      mesh_.PutTriangle(new_id[written[k]], rows[k]);
    }
    size_t k = written.size();  // paint index of the first stored triangle around

    // R's rows go: the whole surface's in one statement, a local region's one by one.
    TB_RETURN_IF_ERROR(Step());
    if (whole_surface_) {
      TB_ASSIGN_OR_RETURN(Statement * del_all,
                          db.Cached("DELETE FROM triangles WHERE surface = ? AND id < ?"));
      TB_RETURN_IF_ERROR(del_all->Bind(1, surface_.id).Bind(2, base).Run());
      if (db.Changes() != static_cast<int64_t>(order_.size()))
        return Status::Corruption(
            "surface '" + surface_.name + "': " + std::to_string(db.Changes()) +
            " triangle rows instead of " + std::to_string(order_.size()) + " were replaced");
    } else {
      // One statement per run of consecutive ids: R's triangles were mostly written together
      // (block order), so a run is often dozens of rows. (An IN list of the ids of short runs
      // cost more: SQLite builds a temporary table of them for each statement.)
      std::vector<int64_t> ids_in_r = order_;
      std::sort(ids_in_r.begin(), ids_in_r.end());
      TB_ASSIGN_OR_RETURN(Statement * del,
                          db.Cached("DELETE FROM triangles WHERE id BETWEEN ? AND ?"));
      for (size_t first = 0; first < ids_in_r.size();) {
        size_t last = first;
        while (last + 1 < ids_in_r.size() && ids_in_r[last + 1] == ids_in_r[last] + 1) ++last;
        TB_RETURN_IF_ERROR(del->Bind(1, ids_in_r[first]).Bind(2, ids_in_r[last]).Run());
        first = last + 1;
      }
      for (int64_t t : order_) mesh_.ForgetTriangle(t);
    }
    TB_ASSIGN_OR_RETURN(Statement * del_vertex, db.Cached("DELETE FROM vertices WHERE id = ?"));
    for (int64_t v : dropped_) {
      TB_RETURN_IF_ERROR(del_vertex->Bind(1, v).Run());
      mesh_.ForgetVertex(v);
    }
    result_.removed = static_cast<int64_t>(order_.size());
    if (whole_surface_) mesh_.ForgetAllRows();

    // Outer triangles point across the outline at the new triangles.
    TB_RETURN_IF_ERROR(Step());
    EdgeTable inner_by_edge;  // store (a, b) -> new triangle
    // R's outline has no triangle across when R is the whole surface.
    if (!outer_across.empty()) {
      for (uint32_t t : written) {
        const auto& v = tin.triangles[t].v;
        for (int i = 0; i < 3; ++i)
          inner_by_edge.Add(Edge{ids[v[i]], ids[v[(i + 1) % 3]]}, new_id[t]);
      }
    }
    inner_by_edge.Seal();
    std::map<int64_t, MeshTriangle> relinked;
    for (const OutlineEdge& e : outline_) {
      if (!e.outer) continue;
      const int64_t* inner = inner_by_edge.Find(Edge{e.a, e.b});
      if (inner == nullptr)
        return Status::Corruption("outline edge (" + std::to_string(e.a) + ", " +
                                  std::to_string(e.b) + ") vanished from the patch");
      auto [entry, fresh] = relinked.emplace(*e.outer, MeshTriangle{});
      if (fresh) {
        TB_ASSIGN_OR_RETURN(const MeshTriangle* outer, mesh_.Triangle(*e.outer));
        entry->second = *outer;
      }
      MeshTriangle& outer = entry->second;
      for (int j = 0; j < 3; ++j)
        if (outer.v[(j + 1) % 3] == e.b && outer.v[(j + 2) % 3] == e.a) outer.n[j] = *inner;
    }
    // One UPDATE a row: cheaper than batches, whether REPLACE of whole rows or UPDATE ... FROM
    // a VALUES list (both measured).
    TB_ASSIGN_OR_RETURN(Statement * relink,
                        db.Cached("UPDATE triangles SET n0 = ?, n1 = ?, n2 = ? WHERE id = ?"));
    for (const auto& [id, t] : relinked) {
      for (int i = 0; i < 3; ++i) {
        if (t.n[i])
          relink->Bind(1 + i, *t.n[i]);
        else
          relink->BindNull(1 + i);
      }
      TB_RETURN_IF_ERROR(relink->Bind(4, id).Run());
      mesh_.PutTriangle(id, t);
    }

    // Constraints: the removed features' rows go; kept constraints split by new points or
    // crossings are re-written piece by piece; the new polylines' pieces get their feature.
    TB_RETURN_IF_ERROR(Step());
    TB_ASSIGN_OR_RETURN(Statement * del_feature,
                        db.Cached("DELETE FROM constraints WHERE surface = ? AND feature = ?"));
    for (int64_t f : edit_.remove)
      TB_RETURN_IF_ERROR(del_feature->Bind(1, surface_.id).Bind(2, f).Run());
    if (!edit_.remove.empty()) mesh_.ForgetAllOwners();
    std::vector<std::vector<uint32_t>> graph(tin.vertices.size());  // constrained neighbours
    for (const auto& [a, b] : tin.constraints) graph[a].push_back(b), graph[b].push_back(a);
    TB_ASSIGN_OR_RETURN(
        Statement * del_edge,
        db.Cached("DELETE FROM constraints WHERE surface = ? AND va = ? AND vb = ?"));
    // Sorted and made unique before use (a large edit adds thousands: sets cost more).
    std::vector<std::pair<Edge, int64_t>> added_edges;  // (edge, feature), written in bulk below
    std::vector<Edge> accounted;  // store edges that are constraints after the edit, or R's outline
    const auto add_row = [&](const Edge& e, int64_t feature) {
      accounted.push_back(e);
      added_edges.push_back({e, feature});
    };
    const auto write_pieces = [&](uint32_t a, uint32_t b, int64_t feature) -> Status {
      TB_ASSIGN_OR_RETURN(auto pieces, Pieces(graph, tin, a, b));
      for (const auto& [u, w] : pieces) add_row(Key(ids[u], ids[w]), feature);
      return Status::Ok();
    };
    // The features that new segments running along a kept constraint add to its owners.
    std::map<Edge, std::vector<int64_t>> joining = std::move(present_);
    for (const auto& [edge, owners] : patch.old_constraints) {
      const uint32_t a = local_.at(edge.first), b = local_.at(edge.second);
      std::vector<int64_t> joined;
      if (auto it = joining.find(edge); it != joining.end()) {
        joined = std::move(it->second);
        joining.erase(it);
      }
      bool whole = false;
      for (uint32_t w : graph[a]) whole |= w == b;
      if (whole) {
        accounted.push_back(edge);
        for (int64_t f : joined) add_row(edge, f);
        continue;
      }
      TB_RETURN_IF_ERROR(
          del_edge->Bind(1, surface_.id).Bind(2, edge.first).Bind(3, edge.second).Run());
      mesh_.SetUnconstrained(edge.first, edge.second);
      for (int64_t f : owners) TB_RETURN_IF_ERROR(write_pieces(a, b, f));
      for (int64_t f : joined) TB_RETURN_IF_ERROR(write_pieces(a, b, f));
    }
    // Outside R the edge is as it was.
    for (const auto& [edge, features] : joining)
      for (int64_t f : features) add_row(edge, f);
    for (size_t l = 0; l < lines_.size(); ++l) {
      const std::vector<uint32_t>& idx = patch.lines[l];
      const size_t n = idx.size();
      const size_t segments = lines_[l].closed ? n : n - 1;
      for (size_t i = 0; i < segments; ++i)
        if (idx[i] != idx[(i + 1) % n])
          TB_RETURN_IF_ERROR(write_pieces(idx[i], idx[(i + 1) % n], lines_[l].feature));
    }
    // In the order of the (surface, va, vb) index, so that its entries go in one sweep. Every
    // key holds: the surface is this one, each feature is an added one (its row is written
    // before Apply) or an owner of a kept constraint. No edge split above is among them (its
    // pieces are), so the cache learns the owners after SetUnconstrained.
    std::sort(added_edges.begin(), added_edges.end());
    added_edges.erase(std::unique(added_edges.begin(), added_edges.end()), added_edges.end());
    for (const auto& [e, feature] : added_edges) mesh_.AddOwner(e.first, e.second, feature);
    {
      TB_ASSIGN_OR_RETURN(auto unchecked, UncheckedIfWholeSurface());
      TB_RETURN_IF_ERROR(InsertRows(db, "constraints(surface, va, vb, feature)", 4,
                                    added_edges.size(), [&](Statement& row, int p, size_t c) {
                                      const auto& [e, feature] = added_edges[c];
                                      row.Bind(p, surface_.id).Bind(p + 1, e.first);
                                      row.Bind(p + 2, e.second);
                                      if (feature != 0)
                                        row.Bind(p + 3, feature);
                                      else
                                        row.BindNull(p + 3);
                                    }));
    }
    // The new triangles' other edges are unconstrained: said so to the cache, the next edits
    // need not look their rows up (a cache that knows every constraint needs no telling).
    if (!whole_surface_ && !mesh_.knows_every_constraint()) {
      for (uint32_t t : written) {
        const auto& v = tin.triangles[t].v;
        for (int i = 0; i < 3; ++i) {
          const uint32_t a = v[i], b = v[(i + 1) % 3];
          if (std::find(graph[a].begin(), graph[a].end(), b) == graph[a].end())
            mesh_.SetUnconstrained(ids[a], ids[b]);
        }
      }
    }
    // R's outline is constrained only in the patch; on the domain boundary new points may split
    // it (it has no triangle across), so its pieces count too.
    for (const OutlineEdge& e : outline_) {
      TB_ASSIGN_OR_RETURN(auto pieces, Pieces(graph, tin, local_.at(e.a), local_.at(e.b)));
      for (const auto& [u, w] : pieces) accounted.push_back(Key(ids[u], ids[w]));
    }
    std::sort(accounted.begin(), accounted.end());
    // Every edge CGAL constrained must be one we own; one that is not means CGAL rerouted a
    // constraint through another vertex (CGAL#6602) and the edge would be stored unconstrained.
    for (const auto& [a, b] : tin.constraints) {
      if (std::binary_search(accounted.begin(), accounted.end(), Key(ids[a], ids[b]))) continue;
      return Status::Corruption("surface '" + surface_.name +
                                "': a constraint was rerouted through " +
                                FormatPoint({tin.vertices[a].x, tin.vertices[a].y}) + " - " +
                                FormatPoint({tin.vertices[b].x, tin.vertices[b].y}) +
                                " while re-triangulating; nothing was written");
    }

    // Paint of the stored triangles around the changed features, and their vertices' z.
    TB_RETURN_IF_ERROR(Step());
    std::vector<Repaint> repaints;
    for (size_t j = 0; j < kept_around.size(); ++j, ++k) {
      TB_ASSIGN_OR_RETURN(const MeshTriangle* stored, mesh_.Triangle(kept_around[j]));
      const bool visible = paint.visible[k] != 0;
      const std::optional<int64_t> tag = tag_of(k);
      if (stored->visible != visible || stored->tag != tag)
        repaints.push_back({kept_around[j], visible, tag});
    }
    TB_RETURN_IF_ERROR(WriteRepaints(std::move(repaints)));
    TB_RETURN_IF_ERROR(WriteUniformRepaints());
    for (const auto& [id, index] : painted_vertex) {
      (void)index;
      // R's vertices (existing or new) already have their z.
      if (local_.count(id) || dropped_.count(id) || (id >= first_new_vertex && id < end_new_vertex))
        continue;
      TB_ASSIGN_OR_RETURN(const TinVertex* stored, mesh_.Vertex(id));
      const double z = TargetZ(*stored);
      if (z == stored->z) continue;
      TB_RETURN_IF_ERROR(set_z->Bind(1, z).Bind(2, id).Run());
      TinVertex moved = *stored;
      moved.z = z;
      mesh_.PutVertex(id, moved);
    }
    return Status::Ok();
  }

  // Binds (surface, v0, v1, v2, n0, n1, n2, visible, tag, block) of `t` from parameter p on.
  void BindTriangleRow(Statement& row, int p, const MeshTriangle& t) const {
    row.Bind(p, surface_.id);
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

  // Consecutive ids from which one statement over their range beats looking each up by id.
  static constexpr size_t kLongRun = 8;

  struct Repaint {
    int64_t triangle;
    bool visible;
    std::optional<int64_t> tag;
  };

  // Long runs of consecutive ids that take the same paint are one UPDATE each: the builders
  // store a surface's triangles in block order, so a filled polygon's inside is a few long runs
  // (a fill over ~5000 triangles of a 1e6 store is ~100 statements instead of 5000), and a run
  // walks the table in id order, twice as fast as looking every row up. The rest (around a ring
  // runs are short: two rows on average in a map loaded feature by feature) are looked up by id,
  // up to 64 of one paint in one statement (an UPDATE costs several times a row's lookup). Rows
  // that already have the paint are not rewritten (uniform blocks' triangles are not read
  // first), and only the rows that change count as repainted.
  Status WriteRepaints(std::vector<Repaint> repaints) {
    std::sort(repaints.begin(), repaints.end(),
              [](const Repaint& a, const Repaint& b) { return a.triangle < b.triangle; });
    TB_ASSIGN_OR_RETURN(Statement * repaint_run,
                        store_.db().Cached("UPDATE triangles SET visible = ?1, tag = ?2 WHERE "
                                           "id BETWEEN ?3 AND ?4 AND "
                                           "(visible IS NOT ?1 OR tag IS NOT ?2)"));
    std::map<std::pair<bool, std::optional<int64_t>>, std::vector<int64_t>> by_paint;
    for (size_t first = 0; first < repaints.size();) {
      const Repaint& paint = repaints[first];
      size_t last = first;
      while (last + 1 < repaints.size() &&
             repaints[last + 1].triangle == repaints[last].triangle + 1 &&
             repaints[last + 1].visible == paint.visible && repaints[last + 1].tag == paint.tag)
        ++last;
      for (size_t k = first; k <= last; ++k)
        mesh_.Repaint(repaints[k].triangle, repaints[k].visible, repaints[k].tag);
      if (last + 1 - first < kLongRun) {
        std::vector<int64_t>& ids = by_paint[{paint.visible, paint.tag}];
        for (size_t k = first; k <= last; ++k) ids.push_back(repaints[k].triangle);
        first = last + 1;
        continue;
      }
      BindPaint(*repaint_run, paint.visible, paint.tag);
      TB_RETURN_IF_ERROR(
          repaint_run->Bind(3, paint.triangle).Bind(4, repaints[last].triangle).Run());
      result_.repainted += store_.db().Changes();
      first = last + 1;
    }
    for (const auto& [paint, ids] : by_paint)
      TB_RETURN_IF_ERROR(RepaintByIds(paint.first, paint.second, ids));
    return Status::Ok();
  }

  static void BindPaint(Statement& stmt, bool visible, const std::optional<int64_t>& tag) {
    stmt.Bind(1, int64_t{visible ? 1 : 0});
    if (tag)
      stmt.Bind(2, *tag);
    else
      stmt.BindNull(2);
  }

  // The rows `ids` take one paint, up to 64 ids a statement.
  Status RepaintByIds(bool visible, const std::optional<int64_t>& tag,
                      const std::vector<int64_t>& ids) {
    return RunOverIds(
        store_.db(), "UPDATE triangles SET visible = ?1, tag = ?2 WHERE id IN",
        " AND (visible IS NOT ?1 OR tag IS NOT ?2)", 2, ids,
        [&](Statement& stmt) { BindPaint(stmt, visible, tag); }, &result_.repainted);
  }

  // The uniform blocks' triangles take their block's paint without being read: the block index
  // holds their ids (it covers the query). Every tag id the UPDATEs bind is interned here, in
  // this transaction (triangles.tag is not a declared foreign key: migration 0009).
  Status WriteUniformRepaints() {
    if (uniform_blocks_.empty()) return Status::Ok();
    std::vector<int64_t> tag_ids;
    for (const std::string& value : uniform_tags_) {
      TB_ASSIGN_OR_RETURN(int64_t id, InternTag(store_, value));
      tag_ids.push_back(id);
    }
    TB_ASSIGN_OR_RETURN(Statement * ids_of,
                        store_.db().Cached("SELECT id, block FROM triangles WHERE surface = ? AND "
                                           "block BETWEEN ? AND ?"));
    std::vector<Repaint> repaints;
    // A run of consecutive blocks is one range of the index; block k of it is uniform_blocks_[k].
    for (size_t first = 0; first < uniform_blocks_.size();) {
      size_t last = first;
      while (last + 1 < uniform_blocks_.size() &&
             uniform_blocks_[last + 1] == uniform_blocks_[last] + 1)
        ++last;
      ids_of->Bind(1, surface_.id).Bind(2, uniform_blocks_[first]).Bind(3, uniform_blocks_[last]);
      for (;;) {
        TB_ASSIGN_OR_RETURN(bool row, ids_of->Step());
        if (!row) break;
        const size_t k = first + static_cast<size_t>(ids_of->ColumnInt(1) - uniform_blocks_[first]);
        const int32_t tag = uniform_paint_.tag[k];
        repaints.push_back({ids_of->ColumnInt(0), uniform_paint_.visible[k] != 0,
                            tag == kNoTag ? std::nullopt : std::optional<int64_t>(tag_ids[tag])});
      }
      ids_of->Reset();
      first = last + 1;
    }
    return WriteRepaints(std::move(repaints));
  }

  Store& store_;
  const SurfaceInfo& surface_;
  DemStore& dems_;
  const DemInfo& dem_;
  const LocalEdit& edit_;
  const FaultHook& hook_;
  std::unique_ptr<ScopedPageCache>& page_cache_;  // the engine's: it outlives the commit
  MeshCache& mesh_;       // the caller's (kept across edits) or the engine's own
  PointLocator locator_;  // valid until Write: every lookup comes before it
  ReplaceLevels levels_;
  std::vector<Polygon> replace_polygons_;
  std::unique_ptr<PolygonLocator> replaced_;      // cells where tolerance does not apply
  std::unique_ptr<PolygonLocator> restore_;       // removed replace features: z back from the DEM
  std::vector<EditPolyline> lines_;               // edit.add, snapped
  std::vector<std::vector<int64_t>> located_;     // a triangle holding each point of lines_
  std::vector<std::vector<int64_t>> snapped_to_;  // the stored vertex each point snapped onto, or 0
  // Kept constrained edges that new segments run along (SetAsidePresentSegments): their features.
  std::map<Edge, std::vector<int64_t>> present_;
  std::vector<EditorFeature> removed_features_;  // rows of edit.remove, as stored
  std::vector<int64_t> around_;  // stored triangles of mixed blocks whose paint may change
  std::unique_ptr<PolygonLocator> changed_inside_;  // the added and removed features' inside
  bool outside_keeps_paint_ = false;  // a stored triangle outside changed_inside_ keeps its paint
  std::vector<int64_t> uniform_blocks_;    // blocks repainted whole, in (by, bx) order
  Paint uniform_paint_;                    // per uniform block
  std::vector<std::string> uniform_tags_;  // what uniform_paint_.tag indexes
  Box paint_box_;

  std::unordered_set<int64_t> region_;  // R
  std::vector<int64_t> order_;          // R in the order found
  std::set<Edge> removed_edges_;
  // Kept constraints that new points snapped onto: (position along min -> max id, point).
  std::map<Edge, std::vector<std::pair<double, Point2>>> splits_;
  std::set<int64_t> dropped_;
  std::vector<Point2> new_points_;
  std::vector<TinVertex> carried_;  // refinement points of earlier rounds
  std::vector<OutlineEdge> outline_;
  std::unordered_map<int64_t, uint32_t> local_;
  SegmentIndex outline_index_;
  Grid grid_;
  EditResult result_;
  int step_ = 0;
  bool whole_surface_ = false;                // R is every triangle (TakeWholeSurface)
  std::optional<int64_t> surface_triangles_;  // SurfaceTriangles(), once counted
  std::vector<int64_t> surface_ids_;          // every triangle, once the surface is loaded
};

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
  Edit run(store_, surface_, dems_, dem_, edit, fault_hook_, page_cache_, *mesh);
  return run.Run();
}

}  // namespace tinbase
