#include "core/tin/edge_collapse.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#if TINBASE_HAVE_EIGEN
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#else
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_cost.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_placement.h>
#endif
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <vector>

#include "core/geometry/predicates.h"
#include "core/tin/tin_raster.h"

namespace tinbase {
namespace {

namespace SMS = CGAL::Surface_mesh_simplification;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point3>;
using VertexIndex = Mesh::Vertex_index;
using HalfedgeIndex = Mesh::Halfedge_index;
using EdgeIndex = Mesh::Edge_index;
using FaceIndex = Mesh::Face_index;
using OptionalPoint = boost::optional<Point3>;

// What a vertex may become in a collapse (see the header): a free vertex may be removed or moved,
// an outline vertex (on a straight stretch of the boundary) only merged along the boundary into
// its neighbour, a fixed one (corner of the outline, end of a constrained edge, pinched
// boundary) never removed.
enum Rank : uint8_t { kFree = 0, kOutline = 1, kFixed = 2 };

struct Context {
  Mesh mesh;
  Mesh::Property_map<VertexIndex, uint8_t> rank;
  Mesh::Property_map<EdgeIndex, bool> constrained_input;
  uint8_t collapsing_rank = kFree;  // rank of the vertex the current collapse keeps
  int64_t foldovers = 0;
};

// CGAL's edge constraint map, read as the collapse goes: the input's constrained edges, and
// boundary edges between two fixed vertices (collapsing one would cut a corner). Boundary edges
// come and go as collapses along the boundary merge them, so this is computed, not stored.
class ConstrainedEdgeMap {
 public:
  using key_type = EdgeIndex;
  using value_type = bool;
  using reference = bool;
  using category = boost::readable_property_map_tag;

  explicit ConstrainedEdgeMap(const Context* ctx = nullptr) : ctx_(ctx) {}
  friend bool get(const ConstrainedEdgeMap& map, EdgeIndex e) {
    const Context& ctx = *map.ctx_;
    if (ctx.constrained_input[e]) return true;
    if (!ctx.mesh.is_border(e)) return false;
    const HalfedgeIndex h = ctx.mesh.halfedge(e);
    return ctx.rank[ctx.mesh.source(h)] == kFixed && ctx.rank[ctx.mesh.target(h)] == kFixed;
  }

 private:
  const Context* ctx_;
};

// True when every triangle that survives collapsing the profile's edge (one with exactly one of
// its two vertices) still turns strictly counter-clockwise in plan view with that vertex moved to
// `placement`. Then the new fan covers the old fan's region exactly once: nothing folds over,
// nothing leaves the domain.
template <typename Profile>
bool FansStayUnfolded(const Mesh& mesh, const Profile& profile, const Point3& placement) {
  const VertexIndex ends[2] = {profile.v0(), profile.v1()};
  const Point2 moved{placement.x(), placement.y()};
  for (VertexIndex end : ends) {
    for (HalfedgeIndex h : CGAL::halfedges_around_target(end, mesh)) {
      const FaceIndex f = mesh.face(h);
      if (f == Mesh::null_face()) continue;
      Point2 corner[3];
      int on_edge = 0, i = 0;
      for (VertexIndex w : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
        if (w == ends[0] || w == ends[1]) {
          ++on_edge;
          corner[i++] = moved;
        } else {
          const Point3& p = mesh.point(w);
          corner[i++] = Point2{p.x(), p.y()};
        }
      }
      if (on_edge == 2) continue;  // the collapse removes this triangle
      if (Orientation(corner[0], corner[1], corner[2]) <= 0) return false;
    }
  }
  return true;
}

// Wraps a strategy's placement with the outline rules (the role of CGAL's Constrained_placement,
// which only knows constrained edges): when an endpoint is on the boundary or fixed, the new
// vertex is that endpoint; a boundary vertex may go only along a boundary edge; a fixed one
// never. `Base` places collapses between two free vertices.
template <class Base>
class OutlinePlacement {
 public:
  OutlinePlacement(const Context* ctx, const Base* base) : ctx_(ctx), base_(base) {}

  template <typename Profile>
  OptionalPoint operator()(const Profile& profile) const {
    const uint8_t r0 = ctx_->rank[profile.v0()];
    const uint8_t r1 = ctx_->rank[profile.v1()];
    if (r0 == kFree && r1 == kFree) return FreePlacement(profile);
    const bool keep_v0 = r0 >= r1;
    const uint8_t removed = keep_v0 ? r1 : r0;
    if (removed == kFixed) return boost::none;
    const bool along_boundary = profile.is_v0_v1_a_border() || profile.is_v1_v0_a_border();
    if (removed == kOutline && !along_boundary) return boost::none;
    return keep_v0 ? profile.p0() : profile.p1();
  }

 private:
  // The strategy's point; when that folds a fan, the endpoint nearer to it, then the other (a
  // quadric optimum far off in a steep fan is common, and refusing such collapses outright would
  // leave the budget out of reach on rough terrain). The cost is then computed for the point
  // actually used. A point that folds every way is returned as is for the filter to refuse.
  template <typename Profile>
  OptionalPoint FreePlacement(const Profile& profile) const {
    const OptionalPoint wanted = (*base_)(profile);
    if (!wanted || FansStayUnfolded(ctx_->mesh, profile, *wanted)) return wanted;
    const bool v0_first = CGAL::squared_distance(*wanted, profile.p0()) <=
                          CGAL::squared_distance(*wanted, profile.p1());
    for (const Point3& end :
         {v0_first ? profile.p0() : profile.p1(), v0_first ? profile.p1() : profile.p0()}) {
      if (FansStayUnfolded(ctx_->mesh, profile, end)) return end;
    }
    return wanted;
  }

  const Context* ctx_;
  const Base* base_;
};

// The last word on every collapse, whatever placed it: CGAL collapses to the placement it
// computed, and a filter can only accept or refuse it (returning another point has no effect).
class NoFoldOverFilter {
 public:
  explicit NoFoldOverFilter(Context* ctx) : ctx_(ctx) {}

  template <typename Profile>
  OptionalPoint operator()(const Profile& profile, OptionalPoint placement) const {
    if (!placement || FansStayUnfolded(ctx_->mesh, profile, *placement)) return placement;
    ++ctx_->foldovers;
    return boost::none;
  }

 private:
  Context* ctx_;
};

// Keeps the rank of the vertex a collapse leaves: CGAL may keep either vertex record and move it
// to the placement, which is where the higher-ranked endpoint was.
class RankVisitor {
 public:
  explicit RankVisitor(Context* ctx) : ctx_(ctx) {}
  void OnStarted(Mesh&) const {}
  void OnFinished(Mesh&) const {}
  template <class Profile>
  void OnStopConditionReached(const Profile&) const {}
  template <class Profile, class OFT>
  void OnCollected(const Profile&, const OFT&) const {}
  template <class Profile, class OFT, class Size>
  void OnSelected(const Profile&, const OFT&, Size, Size) const {}
  template <class Profile, class OPoint>
  void OnCollapsing(const Profile& profile, const OPoint&) const {
    ctx_->collapsing_rank = std::max(ctx_->rank[profile.v0()], ctx_->rank[profile.v1()]);
  }
  template <class Profile>
  void OnCollapsed(const Profile&, VertexIndex kept) const {
    ctx_->rank[kept] = ctx_->collapsing_rank;
  }
  template <class Profile>
  void OnNonCollapsable(const Profile&) const {}

 private:
  Context* ctx_;
};

class FaceBudgetStop {
 public:
  FaceBudgetStop(const Mesh* mesh, int64_t budget) : mesh_(mesh), budget_(budget) {}
  template <typename F, typename Profile>
  bool operator()(const F&, const Profile&, std::size_t, std::size_t) const {
    return static_cast<int64_t>(mesh_->number_of_faces()) <= budget_;
  }

 private:
  const Mesh* mesh_;
  int64_t budget_;
};

// Paper 002's order: short edges first, then small height difference, then low degree. The three
// are multiplied so each breaks the others' ties and none needs a unit: plan length in map units,
// times (1 + |dz| / mean edge length), a slope-like factor that doubles the cost of an edge as
// steep as 45 degrees over a typical edge, times the degree sum over 12 (two vertices of a
// regular triangulation), so collapses that would make busy vertices busier wait.
class ShortFlatLowDegreeCost {
 public:
  ShortFlatLowDegreeCost(const Mesh* mesh, double mean_length)
      : mesh_(mesh), mean_length_(mean_length) {}

  template <typename Profile>
  boost::optional<typename Profile::FT> operator()(const Profile& profile,
                                                   const OptionalPoint& placement) const {
    if (!placement) return boost::none;
    const Point3& p = profile.p0();
    const Point3& q = profile.p1();
    const double length = std::hypot(p.x() - q.x(), p.y() - q.y());
    const double slope = std::fabs(p.z() - q.z()) / mean_length_;
    const double degrees =
        static_cast<double>(mesh_->degree(profile.v0()) + mesh_->degree(profile.v1()));
    return length * (1 + slope) * degrees / 12.0;
  }

 private:
  const Mesh* mesh_;
  double mean_length_;
};

// The paper's placement: the new vertex is one of the endpoints, so it stays a DEM sample. The
// one kept is the one that stands out more from its neighbours (|z - their mean z|): a peak or a
// pit survives, a vertex on an even slope goes.
class SalientEndpointPlacement {
 public:
  explicit SalientEndpointPlacement(const Mesh* mesh) : mesh_(mesh) {}

  template <typename Profile>
  OptionalPoint operator()(const Profile& profile) const {
    return Departure(profile.v0()) >= Departure(profile.v1()) ? profile.p0() : profile.p1();
  }

 private:
  double Departure(VertexIndex v) const {
    double sum = 0;
    int count = 0;
    for (VertexIndex w : CGAL::vertices_around_target(mesh_->halfedge(v), *mesh_)) {
      sum += mesh_->point(w).z();
      ++count;
    }
    return count == 0 ? 0 : std::fabs(mesh_->point(v).z() - sum / count);
  }
  const Mesh* mesh_;
};

// Copies the Tin into ctx->mesh. InvalidArgument naming the triangle or constraint at fault.
Status BuildMesh(const Tin& input, Context* ctx) {
  Mesh& mesh = ctx->mesh;
  mesh.reserve(input.vertices.size(), input.triangles.size() * 3 / 2 + input.vertices.size(),
               input.triangles.size());
  for (const TinVertex& v : input.vertices) mesh.add_vertex(Point3(v.x, v.y, v.z));
  for (size_t t = 0; t < input.triangles.size(); ++t) {
    const auto& v = input.triangles[t].v;
    const std::string where = "triangle " + std::to_string(t);
    for (uint32_t i : v) {
      if (i >= input.vertices.size())
        return Status::InvalidArgument(where + ": vertex " + std::to_string(i) + " does not exist");
    }
    const auto plan = [&](uint32_t i) { return Point2{input.vertices[i].x, input.vertices[i].y}; };
    if (Orientation(plan(v[0]), plan(v[1]), plan(v[2])) <= 0)
      return Status::InvalidArgument(where + ": not counter-clockwise in plan view");
    if (mesh.add_face(VertexIndex(v[0]), VertexIndex(v[1]), VertexIndex(v[2])) ==
        Mesh::null_face()) {
      return Status::InvalidArgument(
          where +
          ": the triangles do not form a manifold surface (an edge used twice in one "
          "direction or by three triangles, or a vertex where two fans meet)");
    }
  }
  ctx->rank = mesh.add_property_map<VertexIndex, uint8_t>("v:tinbase_rank", kFree).first;
  ctx->constrained_input =
      mesh.add_property_map<EdgeIndex, bool>("e:tinbase_constrained", false).first;
  for (size_t k = 0; k < input.constraints.size(); ++k) {
    const auto [a, b] = input.constraints[k];
    const HalfedgeIndex h = a < input.vertices.size() && b < input.vertices.size()
                                ? mesh.halfedge(VertexIndex(a), VertexIndex(b))
                                : Mesh::null_halfedge();
    if (h == Mesh::null_halfedge())
      return Status::InvalidArgument("constraint " + std::to_string(k) + ": not an edge");
    ctx->constrained_input[mesh.edge(h)] = true;
    ctx->rank[VertexIndex(a)] = ctx->rank[VertexIndex(b)] = kFixed;
  }
  return Status::Ok();
}

// Boundary vertices: outline when strictly between their two boundary neighbours on one line,
// fixed otherwise (corners, and vertices where the boundary passes twice).
void RankBoundary(Context* ctx) {
  const Mesh& mesh = ctx->mesh;
  for (VertexIndex v : mesh.vertices()) {
    if (ctx->rank[v] == kFixed || mesh.is_isolated(v)) continue;
    int border_halfedges = 0;
    HalfedgeIndex in;
    for (HalfedgeIndex h : CGAL::halfedges_around_target(v, mesh)) {
      if (mesh.is_border(h)) {
        ++border_halfedges;
        in = h;
      }
    }
    if (border_halfedges == 0) continue;
    if (border_halfedges > 1) {
      ctx->rank[v] = kFixed;
      continue;
    }
    const Point3& p = mesh.point(mesh.source(in));
    const Point3& q = mesh.point(v);
    const Point3& r = mesh.point(mesh.target(mesh.next(in)));
    const bool straight = Orientation({p.x(), p.y()}, {q.x(), q.y()}, {r.x(), r.y()}) == 0 &&
                          (p.x() - q.x()) * (r.x() - q.x()) + (p.y() - q.y()) * (r.y() - q.y()) < 0;
    ctx->rank[v] = straight ? kOutline : kFixed;
  }
}

double MeanPlanEdgeLength(const Mesh& mesh) {
  double sum = 0;
  for (EdgeIndex e : mesh.edges()) {
    const Point3& p = mesh.point(mesh.source(mesh.halfedge(e)));
    const Point3& q = mesh.point(mesh.target(mesh.halfedge(e)));
    sum += std::hypot(p.x() - q.x(), p.y() - q.y());
  }
  return mesh.number_of_edges() == 0 ? 1 : sum / static_cast<double>(mesh.number_of_edges());
}

struct BitsHash {
  size_t operator()(const std::pair<double, double>& p) const {
    return std::hash<double>()(p.first) * 1000003u ^ std::hash<double>()(p.second);
  }
};

// The mesh back in table layout; a surviving vertex at an input vertex's position keeps its kind.
Tin ToTin(const Tin& input, const Context& ctx) {
  const Mesh& mesh = ctx.mesh;
  std::unordered_map<std::pair<double, double>, uint32_t, BitsHash> input_at;
  input_at.reserve(input.vertices.size());
  for (size_t i = 0; i < input.vertices.size(); ++i)
    input_at.emplace(std::make_pair(input.vertices[i].x, input.vertices[i].y),
                     static_cast<uint32_t>(i));

  Tin tin;
  constexpr uint32_t kUnused = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> index(mesh.num_vertices(), kUnused);
  const auto index_of = [&](VertexIndex v) {
    uint32_t& i = index[static_cast<size_t>(v.idx())];
    if (i != kUnused) return i;
    i = static_cast<uint32_t>(tin.vertices.size());
    const Point3& p = mesh.point(v);
    TinVertex out{p.x(), p.y(), p.z(), VertexKind::kSteiner};
    const auto it = input_at.find({p.x(), p.y()});
    if (it != input_at.end() && input.vertices[it->second].z == p.z())
      out.kind = input.vertices[it->second].kind;
    tin.vertices.push_back(out);
    return i;
  };
  tin.triangles.reserve(mesh.number_of_faces());
  for (FaceIndex f : mesh.faces()) {
    TinTriangle t;
    int i = 0;
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) t.v[i++] = index_of(v);
    tin.triangles.push_back(t);
  }
  for (EdgeIndex e : mesh.edges()) {
    if (!ctx.constrained_input[e]) continue;
    tin.constraints.emplace_back(index_of(mesh.source(mesh.halfedge(e))),
                                 index_of(mesh.target(mesh.halfedge(e))));
  }
  return tin;
}

template <class Cost, class Placement>
void Collapse(Context* ctx, int64_t budget, const Cost& cost, const Placement& placement) {
  SMS::edge_collapse(ctx->mesh, FaceBudgetStop(&ctx->mesh, budget),
                     CGAL::parameters::get_cost(cost)
                         .get_placement(OutlinePlacement<Placement>(ctx, &placement))
                         .filter(NoFoldOverFilter(ctx))
                         .edge_is_constrained_map(ConstrainedEdgeMap(ctx))
                         .visitor(RankVisitor(ctx)));
}

}  // namespace

const char* CollapseStrategyName(CollapseStrategy strategy) {
  switch (strategy) {
    case CollapseStrategy::kGarlandHeckbert:
      return "quadric";
    case CollapseStrategy::kShortFlatLowDegree:
      return "paper";
  }
  return "quadric";
}

bool ParseCollapseStrategy(const std::string& name, CollapseStrategy* strategy) {
  for (CollapseStrategy s :
       {CollapseStrategy::kGarlandHeckbert, CollapseStrategy::kShortFlatLowDegree}) {
    if (name == CollapseStrategyName(s)) {
      *strategy = s;
      return true;
    }
  }
  return false;
}

Result<Tin> CollapseToFaceBudget(const Tin& input, const CollapseOptions& options,
                                 CollapseReport* report, const Grid* reference) {
  if (options.faces < 2)
    return Status::InvalidArgument("face budget " + std::to_string(options.faces) +
                                   ": at least 2 faces are needed");
  if (input.triangles.empty()) return Status::InvalidArgument("the TIN has no triangle");
  Context ctx;
  TB_RETURN_IF_ERROR(BuildMesh(input, &ctx));
  RankBoundary(&ctx);

  switch (options.strategy) {
    case CollapseStrategy::kGarlandHeckbert: {
#if TINBASE_HAVE_EIGEN
      SMS::GarlandHeckbert_plane_policies<Mesh, K> quadrics(ctx.mesh);
      Collapse(&ctx, options.faces, quadrics.get_cost(), quadrics.get_placement());
#else
      Collapse(&ctx, options.faces, SMS::LindstromTurk_cost<Mesh>(),
               SMS::LindstromTurk_placement<Mesh>());
#endif
      break;
    }
    case CollapseStrategy::kShortFlatLowDegree: {
      const ShortFlatLowDegreeCost cost(&ctx.mesh, MeanPlanEdgeLength(ctx.mesh));
      const SalientEndpointPlacement placement(&ctx.mesh);
      Collapse(&ctx, options.faces, cost, placement);
      break;
    }
  }

  Tin tin = ToTin(input, ctx);
  [[maybe_unused]] const bool linked = LinkNeighbours(tin);
  assert(linked);
  if (report != nullptr) {
    *report = CollapseReport{};
    report->faces_in = static_cast<int64_t>(input.triangles.size());
    report->vertices_in = static_cast<int64_t>(input.vertices.size());
    report->faces_out = static_cast<int64_t>(tin.triangles.size());
    report->vertices_out = static_cast<int64_t>(tin.vertices.size());
    report->foldovers_refused = ctx.foldovers;
    report->budget_met = report->faces_out <= options.faces;
    if (reference != nullptr) {
      const TinGridError error = CompareTinToGrid(tin, *reference);
      report->max_error = error.max_error;
      report->rms_error = error.rms_error;
      report->cells_compared = error.cells;
    }
  }
  return tin;
}

}  // namespace tinbase
