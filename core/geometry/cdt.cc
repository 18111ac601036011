#include "core/geometry/cdt.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Projection_traits_xy_3.h>
#include <CGAL/Spatial_sort_traits_adapter_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <unordered_map>
#include <utility>

namespace tinbase {
namespace {

// A vertex CGAL created at a constraint crossing has no index until ToTin gives it one.
constexpr uint32_t kNoIndex = UINT32_MAX;
// Created by the current insertion call, index not yet assigned.
constexpr uint32_t kPending = UINT32_MAX - 1;

struct VertexInfo {
  uint32_t index = kNoIndex;
};
struct FaceInfo {
  uint64_t stamp = 0;
  int32_t id = kNoNeighbour;  // position in Tin::triangles, set by ToTin
};

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Gt = CGAL::Projection_traits_xy_3<K>;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, Gt>;
using Fbb = CGAL::Triangulation_face_base_with_info_2<FaceInfo, Gt>;
using Fb = CGAL::Constrained_triangulation_face_base_2<Gt, Fbb>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// Exact_predicates_tag: crossing constraints are allowed and split at a constructed point.
using Triangulation =
    CGAL::Constrained_Delaunay_triangulation_2<Gt, Tds, CGAL::Exact_predicates_tag>;
using Point = Triangulation::Point;
using VertexHandle = Triangulation::Vertex_handle;
using FaceHandle = Triangulation::Face_handle;

Point ToPoint(const TinVertex& v) { return Point(v.x, v.y, v.z); }

// Whether f's closed circumdisk lies strictly below `limit`, so no point at y >= limit can be in
// or on f's circumcircle. The disk's top, a.y + uy + r with (ux, uy) the circumcentre relative to
// vertex a, is bounded above in interval arithmetic: rounding can only make the answer "no". A
// near-flat face, whose circumcentre the intervals cannot bound, gets "no" too.
// REQUIRES: rounding towards +infinity (a CGAL::Protect_FPU_rounding<true> in scope), which
// unprotected intervals need and which one guard per scan sets, not one per operation.
bool CircumdiskBelow(FaceHandle f, double limit) {
  using I = CGAL::Interval_nt<false>;
  const Point& a = f->vertex(0)->point();
  const Point& b = f->vertex(1)->point();
  const Point& c = f->vertex(2)->point();
  const I bx = I(b.x()) - a.x(), by = I(b.y()) - a.y();
  const I cx = I(c.x()) - a.x(), cy = I(c.y()) - a.y();
  const I d = 2 * (bx * cy - by * cx);
  if (!(d.inf() > 0 || d.sup() < 0)) return false;
  const I b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
  const I ux = (cy * b2 - by * c2) / d, uy = (bx * c2 - cx * b2) / d;
  const I top = I(a.y()) + uy + CGAL::sqrt(ux * ux + uy * uy);
  return top.sup() < limit;
}

// Edge i of f, constrained, as a TIN constraint.
void AddConstraint(std::vector<std::pair<uint32_t, uint32_t>>& constraints, FaceHandle f, int i) {
  assert(f->is_constrained(i));
  constraints.emplace_back(f->vertex(Triangulation::cw(i))->info().index,
                           f->vertex(Triangulation::ccw(i))->info().index);
}

}  // namespace

struct Cdt::Impl {
  Triangulation cdt;
  // Vertex handle by index, so constraints can be given as index pairs.
  std::vector<VertexHandle> handles;
  // False until a constraint is inserted: while every edge is unconstrained, a single insertion
  // takes the plain path (InsertUnconstrained).
  bool constrained = false;
  std::vector<FaceHandle> flip_stack;  // InsertUnconstrained's, kept for its capacity

  static FaceRef Ref(FaceHandle f) { return FaceRef{&*f}; }
  FaceHandle Handle(FaceRef r) const {
    return cdt.tds().faces().iterator_to(*static_cast<Triangulation::Face*>(r.opaque));
  }

  // Inserts p; marks a vertex that is new (or an index-less crossing vertex p landed on) as
  // pending so the caller can give it an index.
  VertexHandle Insert(const Point& p, FaceHandle hint) {
    const size_t before = cdt.number_of_vertices();
    VertexHandle v = cdt.insert(p, hint);
    if (cdt.number_of_vertices() != before || v->info().index == kNoIndex) {
      v->info().index = kPending;
    }
    return v;
  }

  // Inserts p, located in the interior of face `loc` (lt FACE) or on its edge li (lt EDGE), into
  // a triangulation without constraints, then flips each edge opposite the new vertex while the
  // vertex lies strictly inside the circle of the face across it (Lawson's flips, which CGAL's
  // Delaunay insertion makes too). A co-circular tie is never flipped, so the diagonal there
  // stays, the choice KeepCocircularDiagonals restores after CGAL's own constrained insertion;
  // that one breaks ties by symbolic perturbation and, after every flip, re-reads the four
  // faces around the quad to restore their constrained flags, which is a third of an insertion
  // on a greedy build. Every face the insertion made or changed is incident to the vertex.
  // REQUIRES: !constrained, dimension 2, p not a vertex.
  VertexHandle InsertUnconstrained(const Point& p, Triangulation::Locate_type lt, FaceHandle loc,
                                   int li) {
    assert(!constrained && cdt.dimension() == 2);
    // Triangulation_2's insertion: the split alone, no flips (the CDT's insert hides it).
    const VertexHandle v = static_cast<CGAL::Triangulation_2<Gt, Tds>&>(cdt).insert(p, lt, loc, li);
    v->info().index = kPending;
    flip_stack.clear();
    Triangulation::Face_circulator fc = cdt.incident_faces(v);
    const Triangulation::Face_circulator done = fc;
    do {
      flip_stack.push_back(fc);
    } while (++fc != done);
    while (!flip_stack.empty()) {
      const FaceHandle f = flip_stack.back();
      flip_stack.pop_back();
      const int i = f->index(v);
      const FaceHandle g = f->neighbor(i);
      if (cdt.is_infinite(f) || cdt.is_infinite(g)) continue;
      if (cdt.side_of_oriented_circle(g, p, false) != CGAL::ON_POSITIVE_SIDE) continue;
      // Both faces hold v afterwards, each with one of g's other edges opposite it.
      cdt.tds().flip(f, i);
      flip_stack.push_back(f);
      flip_stack.push_back(g);
    }
    return v;
  }

  // Flips back each unconstrained edge v-q that the insertion of v made where v, q and the two
  // apices are co-circular: either diagonal is Delaunay there, and CGAL picks by symbolic
  // perturbation (the order of the points), which on a grid DEM, where such ties are everywhere,
  // steers greedy insertion to 3-5 % more triangles than keeping the diagonal that was there
  // before, as Garland-Heckbert's strict in-circle flips (and delatin, hmm) do. Returns the
  // flipped faces that no longer touch v.
  std::vector<FaceHandle> KeepCocircularDiagonals(VertexHandle v) {
    // Edge i of f is unconstrained, between finite faces, and closes a co-circular quad.
    const auto tied = [&](FaceHandle f, int i) {
      const FaceHandle g = f->neighbor(i);
      if (cdt.is_infinite(f) || cdt.is_infinite(g) || f->is_constrained(i)) return false;
      const Point& apex = g->vertex(g->index(f))->point();
      return cdt.side_of_oriented_circle(f, apex, false) == CGAL::ON_ORIENTED_BOUNDARY;
    };
    std::vector<VertexHandle> far_ends;  // of the tied edges around v
    Triangulation::Face_circulator fc = cdt.incident_faces(v);
    const Triangulation::Face_circulator done = fc;
    do {
      FaceHandle f = fc;
      // Edge cw(index of v) joins v to the vertex ccw of it: each edge from v once.
      if (tied(f, cdt.cw(f->index(v)))) far_ends.push_back(f->vertex(cdt.ccw(f->index(v))));
    } while (++fc != done);
    std::vector<FaceHandle> beyond;
    for (VertexHandle q : far_ends) {
      FaceHandle f;
      int i;
      // Earlier flips may have changed the faces: find the edge again and re-test.
      if (!cdt.is_edge(v, q, f, i) || !tied(f, i)) continue;
      FaceHandle g = f->neighbor(i);
      cdt.flip(f, i);  // reuses f and g: one now holds v, the other lies across the new edge
      beyond.push_back(f->has_vertex(v) ? g : f);
    }
    // A later flip may have taken a face back into v's star, or reused it twice.
    std::vector<FaceHandle> out;
    for (FaceHandle f : beyond)
      if (!f->has_vertex(v) && std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
    return out;
  }

  // The infinite faces, one per hull edge.
  std::vector<FaceHandle> HullFaces() const {
    std::vector<FaceHandle> faces;
    Triangulation::Face_circulator fc = cdt.incident_faces(cdt.infinite_vertex());
    const Triangulation::Face_circulator done = fc;
    do {
      faces.push_back(fc);
    } while (++fc != done);
    return faces;
  }

  // Links each infinite face to the two infinite faces beside it: across its edge from the
  // infinite vertex to a hull vertex w lies the other infinite face holding w.
  void LinkAroundInfinity(const std::vector<FaceHandle>& hull_faces) {
    const VertexHandle inf = cdt.infinite_vertex();
    std::unordered_map<const void*, std::pair<FaceHandle, int>> first_at;
    for (FaceHandle f : hull_faces) {
      const int i = f->index(inf);
      for (const int k : {Triangulation::ccw(i), Triangulation::cw(i)}) {
        // The edge opposite vertex k joins the infinite vertex to w.
        const VertexHandle w = f->vertex(3 - i - k);
        const auto [it, first] = first_at.try_emplace(&*w, f, k);
        if (first) continue;
        f->set_neighbor(k, it->second.first);
        it->second.first->set_neighbor(it->second.second, f);
      }
    }
    inf->set_face(hull_faces.front());
  }

  // Lawson's flips from the edges `to_check`: an edge whose opposite vertex lies strictly inside
  // its face's circle is flipped and the quad's four sides checked in turn. A triangulation
  // that is locally Delaunay everywhere is Delaunay, and only the region around the checked
  // edges changes. Returns the faces flips made (each flip remakes its two faces in place).
  std::vector<FaceHandle> FlipUntilDelaunay(
      std::vector<std::pair<VertexHandle, VertexHandle>> to_check) {
    std::vector<FaceHandle> flipped;
    while (!to_check.empty()) {
      const auto [a, b] = to_check.back();
      to_check.pop_back();
      FaceHandle f;
      int i;
      if (!cdt.is_edge(a, b, f, i)) continue;
      const FaceHandle g = f->neighbor(i);
      if (cdt.is_infinite(f) || cdt.is_infinite(g)) continue;
      const VertexHandle c = f->vertex(i);
      const VertexHandle d = g->vertex(cdt.mirror_index(f, i));
      if (cdt.side_of_oriented_circle(f, d->point(), false) != CGAL::ON_POSITIVE_SIDE) continue;
      cdt.flip(f, i);
      flipped.push_back(f);
      flipped.push_back(g);
      to_check.insert(to_check.end(), {{a, c}, {c, b}, {b, d}, {d, a}});
    }
    return flipped;
  }
};

namespace {

// One batch of InsertVerticesInBands: the finite faces not yet handed over that are final (all of
// them when `last`), numbered on from `next` in `order`, and the links that became known of the
// edges in `unlinked` (faces handed over earlier whose neighbour was not final yet), which it
// updates. Finished faces keep their number in FaceInfo::id; the others have kNoNeighbour there.
TriangleBatch FinishFaces(Triangulation& cdt, double limit, bool last, const TriangleOrder& order,
                          int32_t& next, std::vector<std::pair<FaceHandle, int>>& unlinked) {
  std::vector<FaceHandle> faces;
  if (cdt.dimension() == 2) {
    // Only the test runs rounding upwards: `order` must see the default rounding.
    CGAL::Protect_FPU_rounding<true> upward;
    for (FaceHandle f : cdt.finite_face_handles())
      if (f->info().id == kNoNeighbour && (last || CircumdiskBelow(f, limit))) faces.push_back(f);
  }
  std::vector<std::pair<int64_t, uint32_t>> keyed;
  keyed.reserve(faces.size());
  for (size_t k = 0; k < faces.size(); ++k) {
    TinTriangle t;
    for (int i = 0; i < 3; ++i) t.v[i] = faces[k]->vertex(i)->info().index;
    keyed.emplace_back(order(t), static_cast<uint32_t>(k));
  }
  std::stable_sort(keyed.begin(), keyed.end(),
                   [](const auto& p, const auto& q) { return p.first < q.first; });
  TriangleBatch batch;
  batch.first = static_cast<size_t>(next);
  for (const auto& [key, k] : keyed) faces[k]->info().id = next++;
  // Links of earlier batches first: this batch's own unknown edges join the list after.
  std::vector<std::pair<FaceHandle, int>> still;
  for (const auto& [f, i] : unlinked) {
    const FaceHandle g = f->neighbor(i);
    if (!cdt.is_infinite(g) && g->info().id != kNoNeighbour)
      batch.links.push_back({static_cast<uint32_t>(f->info().id), i, g->info().id});
    else if (!last)
      still.emplace_back(f, i);
  }
  batch.triangles.reserve(keyed.size());
  batch.keys.reserve(keyed.size());
  for (const auto& [key, k] : keyed) {
    const FaceHandle f = faces[k];
    TinTriangle t;
    for (int i = 0; i < 3; ++i) {
      t.v[i] = f->vertex(i)->info().index;
      const FaceHandle g = f->neighbor(i);
      if (!cdt.is_infinite(g) && g->info().id != kNoNeighbour)
        t.n[i] = g->info().id;
      else if (!last)
        still.emplace_back(f, i);  // a later point may still put a face across this edge
    }
    batch.triangles.push_back(t);
    batch.keys.push_back(key);
  }
  unlinked = std::move(still);
  return batch;
}

}  // namespace

Cdt::Cdt() : impl_(std::make_unique<Impl>()) {}
Cdt::~Cdt() = default;
Cdt::Cdt(Cdt&&) noexcept = default;
Cdt& Cdt::operator=(Cdt&&) noexcept = default;

std::vector<uint32_t> Cdt::InsertVertices(const std::vector<TinVertex>& points) {
  std::vector<Point> pts;
  pts.reserve(points.size());
  for (const TinVertex& v : points) pts.push_back(ToPoint(v));
  std::vector<size_t> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  using SortTraits =
      CGAL::Spatial_sort_traits_adapter_2<Gt, CGAL::Pointer_property_map<Point>::type>;
  CGAL::spatial_sort(order.begin(), order.end(), SortTraits(CGAL::make_property_map(pts)));

  std::vector<VertexHandle> by_input(points.size());
  FaceHandle hint;
  for (size_t i : order) {
    VertexHandle v = impl_->Insert(pts[i], hint);
    by_input[i] = v;
    hint = v->face();
  }
  // Indices in input order, so the first of several duplicates in the batch owns the vertex.
  std::vector<uint32_t> result(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    VertexHandle v = by_input[i];
    if (v->info().index == kPending) {
      v->info().index = static_cast<uint32_t>(vertices_.size());
      vertices_.push_back(points[i]);
      impl_->handles.push_back(v);
    }
    result[i] = v->info().index;
  }
  return result;
}

void Cdt::InsertVerticesInBands(const std::vector<TinVertex>& points, int bands,
                                const TriangleOrder& order, const TriangleSink& finished) {
  assert(vertices_.empty() && bands >= 1);
  std::vector<Point> pts;
  pts.reserve(points.size());
  for (const TinVertex& v : points) pts.push_back(ToPoint(v));
  // Input positions by y: each band is a run of them, and the first position after a band's run
  // is the lowest point still to come. Sorted as (y, x, position) records, which the sort moves
  // in memory, rather than as positions compared through `points`, which costs a cache miss per
  // comparison.
  struct YKey {
    double y, x;
    size_t position;
  };
  std::vector<YKey> keys(points.size());
  for (size_t i = 0; i < points.size(); ++i) keys[i] = {points[i].y, points[i].x, i};
  std::sort(keys.begin(), keys.end(),
            [](const YKey& a, const YKey& b) { return a.y != b.y ? a.y < b.y : a.x < b.x; });
  std::vector<size_t> by_y(points.size());
  for (size_t i = 0; i < keys.size(); ++i) by_y[i] = keys[i].position;
  keys = {};
  vertices_ = points;
  impl_->handles.assign(points.size(), VertexHandle());
  using SortTraits =
      CGAL::Spatial_sort_traits_adapter_2<Gt, CGAL::Pointer_property_map<Point>::type>;
  FaceHandle hint;
  int32_t next = 0;
  std::vector<std::pair<FaceHandle, int>> unlinked;
  // Where band b starts, by y rank: n (1 - (1 - b / bands)^2). A store writes the rows of each
  // batch while the next band is inserted, and of the last only after it, so a small last band
  // shortens what is left to write once the triangulation is done (at 1e6 points and four
  // bands: 6 % of the triangles instead of 25 %); the price is a longer first band, while the
  // store is busy with vertex rows anyway, and a scan of the faces that covers more of them.
  const auto band_start = [&](int b) {
    const size_t left = static_cast<size_t>(bands - b);
    const size_t n = points.size(), all = static_cast<size_t>(bands) * static_cast<size_t>(bands);
    return by_y.begin() +
           static_cast<ptrdiff_t>(n - n / all * left * left - n % all * left * left / all);
  };
  for (int band = 0; band < bands; ++band) {
    const auto lo = band_start(band);
    const auto hi = band_start(band + 1);
    CGAL::spatial_sort(lo, hi, SortTraits(CGAL::make_property_map(pts)));
    for (auto it = lo; it != hi; ++it) {
      VertexHandle v = impl_->Insert(pts[*it], hint);
      assert(v->info().index == kPending);  // no two points share x, y
      v->info().index = static_cast<uint32_t>(*it);
      impl_->handles[*it] = v;
      hint = v->face();
    }
    const bool last = hi == by_y.end();
    const double limit = last ? std::numeric_limits<double>::infinity() : points[*hi].y;
    finished(FinishFaces(impl_->cdt, limit, last, order, next, unlinked));
  }
}

uint32_t Cdt::InsertVertex(const TinVertex& point, FaceRef hint, std::vector<FaceRef>* incident) {
  const FaceHandle start = hint.opaque != nullptr ? impl_->Handle(hint) : FaceHandle();
  Triangulation& cdt = impl_->cdt;
  const Point p = ToPoint(point);
  VertexHandle v;
  std::vector<FaceHandle> beyond;
  Triangulation::Locate_type lt = Triangulation::FACE;
  int li = 0;
  const FaceHandle loc =
      !impl_->constrained && cdt.dimension() == 2 ? cdt.locate(p, lt, li, start) : FaceHandle();
  if (loc != FaceHandle() && (lt == Triangulation::FACE || lt == Triangulation::EDGE)) {
    v = impl_->InsertUnconstrained(p, lt, loc, li);
  } else {
    v = impl_->Insert(p, start);
    if (cdt.dimension() == 2) beyond = impl_->KeepCocircularDiagonals(v);
  }
  if (v->info().index == kPending) {
    v->info().index = static_cast<uint32_t>(vertices_.size());
    vertices_.push_back(point);
    impl_->handles.push_back(v);
  }
  if (incident != nullptr) {
    incident->clear();
    if (impl_->cdt.dimension() == 2) {
      Triangulation::Face_circulator fc = impl_->cdt.incident_faces(v);
      const Triangulation::Face_circulator done = fc;
      do {
        if (!impl_->cdt.is_infinite(fc)) incident->push_back(Impl::Ref(fc));
      } while (++fc != done);
      for (FaceHandle f : beyond) incident->push_back(Impl::Ref(f));
    }
  }
  return v->info().index;
}

// The join copies `other`'s faces into this TDS (CGAL cannot move faces between triangulations)
// and links them to this one's faces across the shared hull edges, whose infinite faces on both
// sides go. Both were Delaunay, so only edges near the boundary can fail the test; the flips
// start from the joined edges.
std::vector<uint32_t> Cdt::Absorb(Cdt&& other, std::vector<FaceRef>* changed) {
  Triangulation& cdt = impl_->cdt;
  Triangulation& src = other.impl_->cdt;
  assert(cdt.dimension() == 2 && src.dimension() == 2);
  Tds& tds = cdt.tds();
  const VertexHandle inf = cdt.infinite_vertex();
  const auto xy = [](VertexHandle v) { return std::pair{v->point().x(), v->point().y()}; };
  const auto edge_key = [](VertexHandle a, VertexHandle b) {
    return &*a < &*b ? std::pair{&*a, &*b} : std::pair{&*b, &*a};
  };
  const auto finite_edge = [](FaceHandle f, VertexHandle infinite) {
    const int i = f->index(infinite);
    return std::pair{f->vertex(Triangulation::ccw(i)), f->vertex(Triangulation::cw(i))};
  };

  // Our hull: its vertices by position, its infinite faces by their finite edge.
  std::map<std::pair<double, double>, VertexHandle> hull_vertex;
  std::map<std::pair<const void*, const void*>, FaceHandle> hull_face;
  const std::vector<FaceHandle> our_hull = impl_->HullFaces();
  for (FaceHandle f : our_hull) {
    const auto [a, b] = finite_edge(f, inf);
    hull_vertex.emplace(xy(a), a);
    hull_face.emplace(edge_key(a, b), f);
  }

  // Vertices: other's on the shared boundary map to ours, the others are copied.
  std::vector<VertexHandle> to(other.impl_->handles.size());
  std::vector<VertexHandle> shared;
  for (FaceHandle f : other.impl_->HullFaces()) {
    const VertexHandle v = finite_edge(f, src.infinite_vertex()).first;
    if (const auto it = hull_vertex.find(xy(v)); it != hull_vertex.end()) {
      to[v->info().index] = it->second;
      shared.push_back(it->second);
    }
  }
  std::vector<uint32_t> index_map(to.size());
  for (size_t k = 0; k < to.size(); ++k) {
    if (to[k] == VertexHandle()) {
      to[k] = tds.create_vertex();
      to[k]->set_point(other.impl_->handles[k]->point());
      to[k]->info().index = static_cast<uint32_t>(vertices_.size());
      vertices_.push_back(other.vertices_[k]);
      impl_->handles.push_back(to[k]);
    }
    index_map[k] = to[k]->info().index;
  }
  const auto map = [&](VertexHandle v) { return src.is_infinite(v) ? inf : to[v->info().index]; };

  // Faces, numbered in their id field: other's infinite faces on the shared boundary are
  // dropped, with ours across the same edges.
  std::vector<FaceHandle> faces;
  for (FaceHandle f : src.all_face_handles()) {
    f->info().id = static_cast<int32_t>(faces.size());
    faces.push_back(f);
  }
  std::vector<FaceHandle> made(faces.size());
  std::vector<FaceHandle> ours_across(faces.size());  // by a dropped face of other's
  std::set<FaceHandle> dropped;
  for (FaceHandle f : faces) {
    if (src.is_infinite(f)) {
      const auto [a, b] = finite_edge(f, src.infinite_vertex());
      if (const auto it = hull_face.find(edge_key(map(a), map(b))); it != hull_face.end()) {
        ours_across[f->info().id] = it->second;
        dropped.insert(it->second);
        continue;
      }
    }
    made[f->info().id] = tds.create_face(map(f->vertex(0)), map(f->vertex(1)), map(f->vertex(2)));
  }
  // Our hull's order, not the set's (by address), for the deletions below: the slots they free
  // are reused by later faces, whose order ToTin and the refiner's scans follow, and addresses
  // differ from run to run.
  std::vector<FaceHandle> hull_faces, to_delete;
  for (FaceHandle f : our_hull) (dropped.count(f) ? to_delete : hull_faces).push_back(f);
  std::vector<std::pair<VertexHandle, VertexHandle>> joined;
  for (FaceHandle f : faces) {
    const FaceHandle copy = made[f->info().id];
    if (copy == FaceHandle()) continue;
    if (src.is_infinite(f)) hull_faces.push_back(copy);
    for (int i = 0; i < 3; ++i) {
      const int n = f->neighbor(i)->info().id;
      if (made[n] != FaceHandle()) {
        copy->set_neighbor(i, made[n]);
      } else if (!src.is_infinite(f)) {
        // Across the shared boundary: our face beyond our dropped infinite face.
        const FaceHandle gone = ours_across[n];
        const FaceHandle ours = gone->neighbor(gone->index(inf));
        copy->set_neighbor(i, ours);
        ours->set_neighbor(ours->index(gone), copy);
        joined.emplace_back(copy->vertex(Triangulation::ccw(i)),
                            copy->vertex(Triangulation::cw(i)));
      }  // else: an infinite face beside a dropped one, linked by LinkAroundInfinity
    }
  }
  for (size_t k = 0; k < to.size(); ++k) {
    const FaceHandle copy = made[other.impl_->handles[k]->face()->info().id];
    if (copy != FaceHandle()) to[k]->set_face(copy);
  }
  for (FaceHandle gone : to_delete) {
    for (int i = 0; i < 3; ++i) {
      const VertexHandle v = gone->vertex(i);
      if (v != inf && v->face() == gone) v->set_face(gone->neighbor(gone->index(inf)));
    }
    tds.delete_face(gone);
  }
  impl_->LinkAroundInfinity(hull_faces);
  other.impl_ = std::make_unique<Impl>();
  other.vertices_.clear();

  std::vector<FaceHandle> touched = impl_->FlipUntilDelaunay(std::move(joined));
  if (changed != nullptr) {
    for (VertexHandle v : shared) {
      Triangulation::Face_circulator fc = cdt.incident_faces(v);
      const Triangulation::Face_circulator done = fc;
      do {
        touched.push_back(fc);
      } while (++fc != done);
    }
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    touched.erase(std::remove_if(touched.begin(), touched.end(),
                                 [&](FaceHandle f) { return cdt.is_infinite(f); }),
                  touched.end());
    // In the order of the faces' vertex indices, not their addresses: the caller scans them in
    // this order, and on ties in error the scan order picks the point, so an address order
    // made the TIN differ between runs.
    const auto key = [](FaceHandle f) {
      std::array<uint32_t, 3> k{f->vertex(0)->info().index, f->vertex(1)->info().index,
                                f->vertex(2)->info().index};
      std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
      return k;
    };
    std::sort(touched.begin(), touched.end(),
              [&](FaceHandle a, FaceHandle b) { return key(a) < key(b); });
    changed->clear();
    for (FaceHandle f : touched) changed->push_back(Impl::Ref(f));
  }
  return index_map;
}

// CGAL constrains a->b by walking from a, splitting at vertices on the segment and at crossing
// constraints. A crossing point is constructed inexactly (CGAL#6602), and the walk then goes on
// from that point, so an existing vertex further along the exact segment may be missed by a
// hair and the constraint pass beside it. Splitting first at every vertex exactly on a->b keeps
// each piece anchored at both ends: round-off can then only move a crossing, never the route.
void Cdt::InsertConstraint(uint32_t a, uint32_t b) {
  assert(a < impl_->handles.size() && b < impl_->handles.size() && a != b);
  impl_->constrained = true;
  const VertexHandle va = impl_->handles[a];
  const VertexHandle vb = impl_->handles[b];
  Triangulation& cdt = impl_->cdt;
  if (cdt.dimension() < 2) {
    cdt.insert_constraint(va, vb);
    return;
  }
  const Point& pa = va->point();
  const Point& pb = vb->point();
  // Along a non-vertical segment order by x, else by y: exact for collinear points.
  const bool by_x = pa.x() != pb.x();
  const auto key = [by_x](const Point& p) { return by_x ? p.x() : p.y(); };
  const double lo = std::min(key(pa), key(pb)), hi = std::max(key(pa), key(pb));
  std::vector<VertexHandle> on_segment;
  Triangulation::Line_face_circulator face = cdt.line_walk(pa, pb, va->face());
  // The walk's guard: the data structure's face count is O(1), CGAL's number_of_faces() walks
  // the convex hull (a third of a large patch's build when asked once per constraint).
  for (size_t steps = 0, limit = cdt.tds().number_of_faces(); steps < limit && !face.is_empty();
       ++steps, ++face) {
    if (cdt.is_infinite(face)) break;
    bool reached_b = false;
    for (int i = 0; i < 3; ++i) {
      const VertexHandle v = face->vertex(i);
      if (v == vb) reached_b = true;
      if (v == va || v == vb) continue;
      const double k = key(v->point());
      if (k > lo && k < hi &&
          cdt.geom_traits().orientation_2_object()(pa, pb, v->point()) == CGAL::COLLINEAR) {
        on_segment.push_back(v);
      }
    }
    if (reached_b) break;
  }
  const bool ascending = key(pa) < key(pb);
  std::sort(on_segment.begin(), on_segment.end(), [&](VertexHandle p, VertexHandle q) {
    return ascending ? key(p->point()) < key(q->point()) : key(p->point()) > key(q->point());
  });
  on_segment.erase(std::unique(on_segment.begin(), on_segment.end()), on_segment.end());
  VertexHandle from = va;
  for (VertexHandle v : on_segment) {
    cdt.insert_constraint(from, v);
    from = v;
  }
  cdt.insert_constraint(from, vb);
}

size_t Cdt::FaceCount() const { return impl_->cdt.number_of_faces(); }

std::vector<Cdt::FaceRef> Cdt::FiniteFaces() const {
  std::vector<FaceRef> faces;
  faces.reserve(impl_->cdt.number_of_faces());
  for (FaceHandle f : impl_->cdt.finite_face_handles()) faces.push_back(Impl::Ref(f));
  return faces;
}

std::array<uint32_t, 3> Cdt::FaceVertices(FaceRef face) const {
  const auto* f = static_cast<const Triangulation::Face*>(face.opaque);
  return {f->vertex(0)->info().index, f->vertex(1)->info().index, f->vertex(2)->info().index};
}

std::array<Cdt::Corner, 3> Cdt::FaceCorners(FaceRef face) const {
  const auto* f = static_cast<const Triangulation::Face*>(face.opaque);
  std::array<Corner, 3> corners;
  for (int i = 0; i < 3; ++i) {
    const VertexHandle v = f->vertex(i);
    const Point& p = v->point();
    corners[static_cast<size_t>(i)] = Corner{v->info().index, p.x(), p.y(), p.z()};
  }
  return corners;
}

uint64_t Cdt::FaceStamp(FaceRef face) const {
  return static_cast<const Triangulation::Face*>(face.opaque)->info().stamp;
}

void Cdt::SetFaceStamp(FaceRef face, uint64_t stamp) {
  static_cast<Triangulation::Face*>(face.opaque)->info().stamp = stamp;
}

std::vector<VoronoiCell> Cdt::VoronoiCells() const {
  const Triangulation& cdt = impl_->cdt;
  assert(std::none_of(cdt.finite_edges_begin(), cdt.finite_edges_end(),
                      [](const auto& e) { return e.first->is_constrained(e.second); }));
  std::vector<VoronoiCell> cells(vertices_.size());
  if (cdt.dimension() < 2) {
    // Collinear or fewer than three points: every cell reaches infinity. Neighbours still follow
    // the edges CGAL keeps in one dimension.
    for (const auto& [f, i] : cdt.finite_edges()) {
      const uint32_t a = f->vertex(Triangulation::cw(i))->info().index;
      const uint32_t b = f->vertex(Triangulation::ccw(i))->info().index;
      cells[a].neighbours.push_back(b);
      cells[b].neighbours.push_back(a);
    }
    return cells;
  }
  using Point2 = K::Point_2;
  for (VertexHandle v : cdt.finite_vertex_handles()) {
    VoronoiCell& cell = cells[v->info().index];
    Triangulation::Vertex_circulator vc = cdt.incident_vertices(v);
    const Triangulation::Vertex_circulator vdone = vc;
    bool on_hull = false;
    do {
      if (cdt.is_infinite(vc)) {
        on_hull = true;
      } else {
        cell.neighbours.push_back(vc->info().index);
      }
    } while (++vc != vdone);
    if (on_hull) continue;
    // The cell's corners are the circumcentres of the incident triangles, in counter-clockwise
    // order. They are taken relative to the vertex so the shoelace sum does not cancel large
    // projected coordinates against each other.
    const Point& o = v->point();
    std::vector<Point2> corners;
    Triangulation::Face_circulator fc = cdt.incident_faces(v);
    const Triangulation::Face_circulator fdone = fc;
    do {
      const Point& a = fc->vertex(0)->point();
      const Point& b = fc->vertex(1)->point();
      const Point& c = fc->vertex(2)->point();
      corners.push_back(CGAL::circumcenter(Point2(a.x() - o.x(), a.y() - o.y()),
                                           Point2(b.x() - o.x(), b.y() - o.y()),
                                           Point2(c.x() - o.x(), c.y() - o.y())));
    } while (++fc != fdone);
    double twice_area = 0;
    for (size_t k = 0; k < corners.size(); ++k) {
      const Point2& p = corners[k];
      const Point2& q = corners[(k + 1) % corners.size()];
      twice_area += p.x() * q.y() - q.x() * p.y();
    }
    cell.bounded = true;
    cell.area = std::abs(twice_area) / 2;
  }
  return cells;
}

void Cdt::IndexCrossings(const ElevationFn& elevation) {
  for (VertexHandle v : impl_->cdt.finite_vertex_handles()) {
    if (v->info().index != kNoIndex) continue;
    assert(elevation);
    const double x = v->point().x();
    const double y = v->point().y();
    const double z = elevation(x, y);
    v->info().index = static_cast<uint32_t>(vertices_.size());
    vertices_.push_back(TinVertex{x, y, z, VertexKind::kSteiner});
    impl_->handles.push_back(v);
    // CGAL constructed the crossing's z; FaceCorners reads the point, which must hold ours. The
    // predicates see only x and y.
    v->set_point(Point(x, y, z));
  }
}

Tin Cdt::ToTin(const ElevationFn& elevation) { return MakeTin(elevation, false); }

Tin Cdt::ReleaseTin(const ElevationFn& elevation) { return MakeTin(elevation, true); }

Tin Cdt::MakeTin(const ElevationFn& elevation, bool take_vertices) {
  Triangulation& cdt = impl_->cdt;
  IndexCrossings(elevation);
  Tin tin;
  if (take_vertices) {
    tin.vertices = std::move(vertices_);
    vertices_.clear();
  } else {
    tin.vertices = vertices_;
  }
  if (cdt.dimension() < 2) {
    // No triangles; the edges CGAL keeps in one dimension may still be constrained.
    for (const auto& [f, i] : cdt.finite_edges())
      if (f->is_constrained(i)) AddConstraint(tin.constraints, f, i);
    return tin;
  }
  // Finite faces are numbered in CGAL's order, infinite ones marked kNoNeighbour, so the walk
  // below reads a neighbour's id alone (not its vertices too, to tell whether it is infinite); the
  // walk needs random access to all faces.
  std::vector<FaceHandle> faces;
  faces.reserve(cdt.tds().number_of_faces());
  int32_t next_id = 0;
  for (FaceHandle f : cdt.all_face_handles()) {
    f->info().id = cdt.is_infinite(f) ? kNoNeighbour : next_id++;
    faces.push_back(f);
  }
  tin.triangles.resize(static_cast<size_t>(next_id));
  // Triangles and constraints in one walk over all faces, which touches each face once instead of
  // once more per edge. Constraints come in finite_edges() order: an edge belongs to the face of
  // its two with the smaller handle (CGAL's edge iterator), and is finite when neither end is
  // the infinite vertex. Each face writes only its own triangle, so the walk is cut into chunks of
  // kFacesPerChunk faces that run in parallel (TBB), each listing its constraints apart; the
  // lists are joined in chunk order, as one walk would list them. The chunks depend on the face
  // count alone, so the result does not depend on the number of threads.
  constexpr size_t kFacesPerChunk = size_t{1} << 15;
  const size_t chunks = (faces.size() + kFacesPerChunk - 1) / kFacesPerChunk;
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> chunk_constraints(chunks);
  const auto walk = [&](size_t chunk) {
    std::vector<std::pair<uint32_t, uint32_t>>& constraints = chunk_constraints[chunk];
    const size_t last = std::min(faces.size(), (chunk + 1) * kFacesPerChunk);
    for (size_t k = chunk * kFacesPerChunk; k < last; ++k) {
      const FaceHandle f = faces[k];
      const bool finite = f->info().id != kNoNeighbour;
      TinTriangle t;
      for (int i = 0; i < 3; ++i) {
        const FaceHandle n = f->neighbor(i);
        if (finite) {
          t.v[i] = f->vertex(i)->info().index;
          t.n[i] = n->info().id;
        }
        if (f->is_constrained(i) && f < n && !cdt.is_infinite(f, i))
          AddConstraint(constraints, f, i);
      }
      if (finite) tin.triangles[static_cast<size_t>(f->info().id)] = t;
    }
  };
  if (chunks == 1) {
    walk(0);
  } else {
    tbb::parallel_for(size_t{0}, chunks, walk);
  }
  for (auto& constraints : chunk_constraints)
    tin.constraints.insert(tin.constraints.end(), constraints.begin(), constraints.end());
  return tin;
}

}  // namespace tinbase
