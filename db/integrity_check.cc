#include "db/integrity_check.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <tuple>
#include <unordered_set>

#include "core/base/paged_id_map.h"
#include "core/geometry/polygon_locator.h"
#include "core/geometry/predicates.h"
#include "core/tin/cell_cover.h"
#include "db/dem_cell_source.h"
#include "db/dem_store.h"
#include "db/edit/line_z.h"
#include "db/feature_store.h"
#include "db/integrity_lines.h"
#include "db/mesh/mesh_rows.h"
#include "db/mesh/mesh_tables.h"
#include "db/surface_store.h"

namespace tinbase {

namespace {

// A triangle row with its id and what CheckTriangles found of it.
struct Row : TriangleRow {
  int64_t id = 0;
  bool valid = false;  // all three vertices exist
  int orientation = 0;
};

// A directed edge a->b of triangle `t` (index into the rows), opposite its vertex `i`.
struct HalfEdge {
  int64_t a = 0, b = 0;
  uint32_t t = 0;
  int i = 0;
  bool operator<(const HalfEdge& o) const { return a != o.a ? a < o.a : b < o.b; }
};

// Checks one surface; reads it with three queries and keeps it in paged id maps and sorted
// vectors, so the whole check is O(n log n).
class SurfaceChecker {
 public:
  SurfaceChecker(Store& store, const SurfaceInfo& surface, bool full,
                 std::vector<Problem>* problems)
      : store_(store), surface_(surface), full_(full), problems_(problems) {}

  Status Run() {
    TB_RETURN_IF_ERROR(Read());
    CheckTriangles();
    CheckTags();
    CheckDuplicateVertices();
    BuildHalfEdges();
    CheckNeighbours();
    CheckEuler();
    CheckWinding();
    CheckConstraints();
    TB_RETURN_IF_ERROR(AddLineProblems(CheckConstraintKinds(store_, surface_)));
    if (surface_.kind == SurfaceKind::kDelaunay) CheckDelaunay();
    CheckBlocks();
    // Paint and tolerance are only meaningful over a sound triangulation.
    if (full_ && problems_->empty()) TB_RETURN_IF_ERROR(CheckPaintAndTolerance());
    return Status::Ok();
  }

 private:
  Status Read() {
    MeshTables tables(store_.db(), surface_);
    {
      TB_ASSIGN_OR_RETURN(VertexCursor vertices, tables.Vertices());
      int64_t id = 0;
      for (VertexRow v;;) {
        TB_ASSIGN_OR_RETURN(bool row, vertices.Next(&id, &v));
        if (!row) break;
        vertex_ids_.push_back(id);
        points_.Put(id, Point2{v.x, v.y});
      }
    }
    {
      TB_ASSIGN_OR_RETURN(TriangleCursor triangles, tables.Triangles());
      for (Row r;;) {
        TB_ASSIGN_OR_RETURN(bool row, triangles.Next(&r.id, &r));
        if (!row) break;
        index_.Put(r.id, static_cast<uint32_t>(rows_.size()));
        rows_.push_back(r);
      }
    }
    TB_ASSIGN_OR_RETURN(const auto tags, tables.TagValues());
    for (const auto& [id, value] : tags) tag_ids_.insert(id);
    {
      TB_ASSIGN_OR_RETURN(ConstraintCursor constraints, tables.Constraints());
      for (ConstraintRow c;;) {
        TB_ASSIGN_OR_RETURN(bool row, constraints.Next(&c));
        if (!row) break;
        constraints_.emplace_back(std::min(c.va, c.vb), std::max(c.va, c.vb));
      }
    }
    std::sort(constraints_.begin(), constraints_.end());
    return Status::Ok();
  }

  void Add(const char* code, std::optional<int64_t> triangle, const std::string& text) {
    std::string message = "surface '" + surface_.name + "'";
    if (triangle) message += ", triangle " + std::to_string(*triangle);
    problems_->push_back({code, surface_.id, triangle, message + ": " + text});
  }

  // REQUIRES: the vertex was read. CheckTriangles marks a row that names a missing vertex invalid,
  // and the checks after it skip invalid rows.
  const Point2& At(int64_t vertex) const { return *points_.Find(vertex); }

  // Invariant 1: vertices exist and turn counter-clockwise.
  void CheckTriangles() {
    for (Row& r : rows_) {
      r.valid = true;
      for (int64_t v : r.v) {
        if (points_.Contains(v)) continue;
        r.valid = false;
        Add("vertex-missing", r.id, "vertex " + std::to_string(v) + " is not in the surface");
      }
      if (!r.valid) continue;
      r.orientation = Orientation(At(r.v[0]), At(r.v[1]), At(r.v[2]));
      if (r.orientation < 0) Add("clockwise-triangle", r.id, "vertices are clockwise");
      if (r.orientation == 0) Add("degenerate-triangle", r.id, "vertices are collinear");
    }
  }

  // Invariant 6's referential half, on every check: triangles.tag is not a declared foreign key
  // (migration 0009).
  void CheckTags() {
    for (const Row& r : rows_)
      if (r.tag && !tag_ids_.count(*r.tag))
        Add("unknown-tag", r.id, "tag " + std::to_string(*r.tag) + " is not a row of tags");
  }

  void CheckDuplicateVertices() {
    std::vector<std::tuple<double, double, int64_t>> order;  // (x, y, id): ids in order on ties
    order.reserve(vertex_ids_.size());
    for (int64_t v : vertex_ids_) order.emplace_back(At(v).x, At(v).y, v);
    std::sort(order.begin(), order.end());
    for (size_t k = 1; k < order.size(); ++k) {
      const auto& [x0, y0, a] = order[k - 1];
      const auto& [x1, y1, b] = order[k];
      if (x0 != x1 || y0 != y1) continue;
      Add("duplicate-vertex", std::nullopt,
          "vertices " + std::to_string(a) + " and " + std::to_string(b) + " share x, y");
    }
  }

  // Sorted directed edges; an edge used twice in one direction is reported on the later
  // triangle (an undirected edge in three triangles necessarily repeats a direction).
  void BuildHalfEdges() {
    half_edges_.reserve(rows_.size() * 3);
    for (uint32_t t = 0; t < rows_.size(); ++t) {
      for (int i = 0; i < 3; ++i)
        half_edges_.push_back({rows_[t].v[(i + 1) % 3], rows_[t].v[(i + 2) % 3], t, i});
    }
    std::sort(half_edges_.begin(), half_edges_.end(), [](const HalfEdge& x, const HalfEdge& y) {
      return x < y || (!(y < x) && x.t < y.t);
    });
    for (size_t k = 1; k < half_edges_.size(); ++k) {
      const HalfEdge& prev = half_edges_[k - 1];
      const HalfEdge& e = half_edges_[k];
      if (prev < e) continue;
      overused_ = true;
      Add("overused-edge", rows_[e.t].id,
          "edge (" + std::to_string(e.a) + ", " + std::to_string(e.b) +
              ") is also used by "
              "triangle " +
              std::to_string(rows_[prev.t].id) + " in the same direction");
    }
  }

  // The first half-edge a->b, or null.
  const HalfEdge* FindHalfEdge(int64_t a, int64_t b) const {
    const HalfEdge key{a, b, 0, 0};
    auto it = std::lower_bound(half_edges_.begin(), half_edges_.end(), key);
    return it != half_edges_.end() && !(key < *it) ? &*it : nullptr;
  }

  std::string EdgeText(const Row& r, int i) const {
    return "(" + std::to_string(r.v[(i + 1) % 3]) + ", " + std::to_string(r.v[(i + 2) % 3]) + ")";
  }

  // Invariant 2: links point to triangles of the surface that share the edge and link back;
  // boundary edges (and only they) have none.
  void CheckNeighbours() {
    for (const Row& r : rows_) {
      for (int i = 0; i < 3; ++i) {
        const int64_t a = r.v[(i + 1) % 3], b = r.v[(i + 2) % 3];
        if (!r.n[i]) {
          if (const HalfEdge* twin = FindHalfEdge(b, a))
            Add("missing-neighbour", r.id,
                "edge " + EdgeText(r, i) + " is shared with triangle " +
                    std::to_string(rows_[twin->t].id) + " but has no neighbour");
          continue;
        }
        const auto across = [&] {
          return "neighbour " + std::to_string(*r.n[i]) + " across edge " + EdgeText(r, i);
        };
        const uint32_t* index = index_.Find(*r.n[i]);
        if (index == nullptr) {
          Add("bad-neighbour", r.id, across() + " is not a triangle of the surface");
          continue;
        }
        const Row& u = rows_[*index];
        int j = 0;
        while (j < 3 && !(u.v[(j + 1) % 3] == b && u.v[(j + 2) % 3] == a)) ++j;
        if (j == 3) {
          Add("neighbour-edge-mismatch", r.id, across() + " does not have that edge");
        } else if (u.n[j] != r.id) {
          Add("asymmetric-neighbour", r.id, across() + " does not name this triangle back");
        }
      }
    }
  }

  // Invariant 3, counts: V - E + F = 2C - B for C edge-connected components with B boundary
  // loops, over the vertices the triangles use; every vertex is used.
  void CheckEuler() {
    std::vector<int64_t> used;
    used.reserve(rows_.size() * 3);
    for (const Row& r : rows_) used.insert(used.end(), r.v.begin(), r.v.end());
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    for (int64_t v : vertex_ids_) {
      if (!std::binary_search(used.begin(), used.end(), v))
        Add("euler", std::nullopt, "vertex " + std::to_string(v) + " is used by no triangle");
    }
    if (overused_ || rows_.empty()) return;  // counts mean nothing then; already reported

    std::vector<uint32_t> parent(rows_.size());
    for (uint32_t t = 0; t < parent.size(); ++t) parent[t] = t;
    const auto find = [&](uint32_t t) {
      while (parent[t] != t) t = parent[t] = parent[parent[t]];
      return t;
    };
    int64_t interior_half_edges = 0;
    std::vector<HalfEdge> boundary;
    for (const HalfEdge& e : half_edges_) {
      if (const HalfEdge* twin = FindHalfEdge(e.b, e.a)) {
        ++interior_half_edges;
        parent[find(e.t)] = find(twin->t);
      } else {
        boundary.push_back(e);
      }
    }
    int64_t components = 0;
    for (uint32_t t = 0; t < parent.size(); ++t) components += find(t) == t;
    const int64_t loops = CountLoops(boundary);
    const int64_t v = static_cast<int64_t>(used.size());
    const int64_t e = static_cast<int64_t>(boundary.size()) + interior_half_edges / 2;
    const int64_t f = static_cast<int64_t>(rows_.size());
    if (v - e + f != 2 * components - loops)
      Add("euler", std::nullopt,
          "V - E + F = " + std::to_string(v - e + f) +
              " but 2C - B = " + std::to_string(2 * components - loops) + " (V " +
              std::to_string(v) + ", E " + std::to_string(e) + ", F " + std::to_string(f) + ", C " +
              std::to_string(components) + ", B " + std::to_string(loops) + ")");
  }

  // Closed walks that use every boundary half-edge once (sorted by start vertex).
  static int64_t CountLoops(const std::vector<HalfEdge>& boundary) {
    std::vector<bool> used(boundary.size(), false);
    int64_t loops = 0;
    for (size_t start = 0; start < boundary.size(); ++start) {
      if (used[start]) continue;
      ++loops;
      size_t k = start;
      while (!used[k]) {
        used[k] = true;
        // Next: an unused boundary half-edge leaving where this one ends.
        auto it = std::lower_bound(boundary.begin(), boundary.end(),
                                   HalfEdge{boundary[k].b, INT64_MIN, 0, 0});
        while (it != boundary.end() && it->a == boundary[k].b && used[it - boundary.begin()]) ++it;
        if (it == boundary.end() || it->a != boundary[k].b) break;
        k = static_cast<size_t>(it - boundary.begin());
      }
    }
    return loops;
  }

  // Invariant 3, tiling: the signed angles of the triangles around a vertex add up to exactly
  // one turn at an interior vertex and to less at a boundary vertex; an extra triangle or a fan
  // wound twice adds at least the smallest angle of some triangle, which is far above the
  // round-off of a few atan2 calls (~1e-15 turns each), so a loose 1e-9 turn tolerance tells
  // them apart.
  void CheckWinding() {
    struct Fan {
      double angle = 0;
      int64_t first_triangle = INT64_MAX;
      bool complete = true;  // every triangle around it could be measured
    };
    PagedIdMap<Fan> fans;
    for (const Row& r : rows_) {
      for (int i = 0; i < 3; ++i) {
        Fan& fan = fans.Emplace(r.v[i], Fan{});
        fan.first_triangle = std::min(fan.first_triangle, r.id);
        if (!r.valid) {
          fan.complete = false;
          continue;
        }
        const Point2 &o = At(r.v[i]), &p = At(r.v[(i + 1) % 3]), &q = At(r.v[(i + 2) % 3]);
        const double ux = p.x - o.x, uy = p.y - o.y, wx = q.x - o.x, wy = q.y - o.y;
        fan.angle += std::atan2(ux * wy - uy * wx, ux * wx + uy * wy);
      }
    }
    std::vector<int64_t> on_boundary;
    for (const HalfEdge& e : half_edges_) {
      if (FindHalfEdge(e.b, e.a)) continue;
      on_boundary.push_back(e.a);
      on_boundary.push_back(e.b);
    }
    std::sort(on_boundary.begin(), on_boundary.end());
    std::vector<int64_t> vertices;  // in id order, so problems come out in a stable order
    vertices.reserve(fans.size());
    fans.ForEach([&](int64_t vertex, const Fan&) { vertices.push_back(vertex); });
    std::sort(vertices.begin(), vertices.end());
    constexpr double kTurn = 2 * std::numbers::pi;
    constexpr double kTolerance = 1e-9;
    for (int64_t vertex : vertices) {
      const Fan& fan = *fans.Find(vertex);
      if (!fan.complete) continue;
      const bool boundary = std::binary_search(on_boundary.begin(), on_boundary.end(), vertex);
      const double turns = fan.angle / kTurn;
      if (boundary ? turns < 1 + kTolerance : std::abs(turns - 1) <= kTolerance) continue;
      char text[160];
      std::snprintf(text, sizeof text, "triangles around %s vertex %lld turn %.9f times around it",
                    boundary ? "boundary" : "interior", static_cast<long long>(vertex), turns);
      Add("overlap", fan.first_triangle, text);
    }
  }

  bool IsConstrained(int64_t a, int64_t b) const {
    return std::binary_search(constraints_.begin(), constraints_.end(),
                              std::make_pair(std::min(a, b), std::max(a, b)));
  }

  // Invariant 4.
  void CheckConstraints() {
    for (const auto& [a, b] : constraints_) {
      if (FindHalfEdge(a, b) || FindHalfEdge(b, a)) continue;
      Add("constraint-not-edge", std::nullopt,
          "constraint (" + std::to_string(a) + ", " + std::to_string(b) +
              ") is not an edge of the triangulation");
    }
  }

  // Invariant 5: across each unconstrained interior edge, the far vertex is not strictly inside
  // the circumcircle (exact; a tie is allowed because grid points are co-circular everywhere).
  // Reported on the lower triangle id of the pair.
  void CheckDelaunay() {
    for (const Row& r : rows_) {
      if (!r.valid || r.orientation <= 0) continue;
      for (int i = 0; i < 3; ++i) {
        const int64_t a = r.v[(i + 1) % 3], b = r.v[(i + 2) % 3];
        const HalfEdge* twin = FindHalfEdge(b, a);
        if (!twin || IsConstrained(a, b)) continue;
        const Row& u = rows_[twin->t];
        if (u.id <= r.id || !u.valid || u.orientation <= 0) continue;
        const int64_t far = u.v[twin->i];
        if (InCircle(At(r.v[0]), At(r.v[1]), At(r.v[2]), At(far)) > 0)
          Add("not-delaunay", r.id,
              "edge " + EdgeText(r, i) + " is not locally Delaunay: vertex " + std::to_string(far) +
                  " of triangle " + std::to_string(u.id) + " is inside the circumcircle");
      }
    }
  }

  // Invariant 8.
  void CheckBlocks() {
    for (const Row& r : rows_) {
      if (!r.valid) continue;
      const Point2 &a = At(r.v[0]), &b = At(r.v[1]), &c = At(r.v[2]);
      const int64_t block = CentroidBlock(surface_.blocks, a.x, a.y, b.x, b.y, c.x, c.y);
      if (block != r.block)
        Add("wrong-block", r.id,
            "block is " + std::to_string(r.block) + " but the centroid is in block " +
                std::to_string(block));
    }
  }

  Status AddLineProblems(Result<std::vector<LineProblem>> found) {
    TB_RETURN_IF_ERROR(found.status());
    for (const auto& [code, text] : *found) Add(code.c_str(), std::nullopt, text);
    return Status::Ok();
  }

  // Invariants 6, 7 and 9, on the surface loaded as a Tin (rows in id order, as rows_).
  Status CheckPaintAndTolerance() {
    TB_ASSIGN_OR_RETURN(LoadedSurface loaded, SurfaceStore(store_).Load(surface_));
    TB_ASSIGN_OR_RETURN(std::vector<EditorFeature> features, LoadFeatures(store_, surface_));
    // The DEM is streamed a block at a time: a store's DEM may be larger than memory.
    DemStore dems(store_);
    std::optional<DemCellSource> dem;
    if (surface_.dem) {
      TB_ASSIGN_OR_RETURN(DemInfo info, dems.FindById(*surface_.dem));
      lines_ = LineElevationOf(features, LineNearDistance(info));
      line_band_ = kLineBandCells * std::max(info.geometry.cell_x, std::fabs(info.geometry.cell_y));
      TB_RETURN_IF_ERROR(AddLineProblems(CheckLineZ(store_, surface_, lines_)));
      dem.emplace(dems, std::move(info));
    }
    Tin& tin = loaded.tin;
    std::vector<std::optional<std::string>> stored_tags;
    stored_tags.reserve(tin.triangles.size());
    for (const TinTriangle& t : tin.triangles)
      stored_tags.push_back(t.tag == kNoTag ? std::nullopt
                                            : std::optional<std::string>(tin.tags[t.tag]));
    const Paint paint =
        PaintFromFeatures(features, dem ? static_cast<CellSource*>(&*dem) : nullptr, tin);
    const auto tag_text = [](const std::optional<std::string>& tag) {
      return tag ? "'" + *tag + "'" : std::string("none");
    };
    for (size_t t = 0; t < tin.triangles.size(); ++t) {
      const int64_t id = loaded.triangle_ids[t];
      if (tin.triangles[t].visible != (paint.visible[t] != 0))
        Add("wrong-visibility", id,
            std::string("visible is ") + (tin.triangles[t].visible ? "1" : "0") +
                " but the features and the DEM's data give " + (paint.visible[t] ? "1" : "0"));
      const std::optional<std::string> expected =
          paint.tag[t] == kNoTag ? std::nullopt
                                 : std::optional<std::string>(tin.tags[paint.tag[t]]);
      if (stored_tags[t] != expected)
        Add("wrong-tag", id,
            "tag is " + tag_text(stored_tags[t]) + " but the features give " + tag_text(expected));
    }
    if (dem && surface_.tolerance) CheckTolerance(tin, loaded.triangle_ids, paint, features, *dem);
    return dem ? dem->status() : Status::Ok();
  }

  // Invariant 7 over the cell centres each visible triangle covers, replace polygons and the
  // bands along 3D lines excepted (db/edit/elevation_rules.h ToleranceExempt).
  // The slack covers the round-off of evaluating a plane from another vertex order.
  void CheckTolerance(const Tin& tin, const std::vector<int64_t>& ids, const Paint& paint,
                      const std::vector<EditorFeature>& features, CellSource& dem) {
    constexpr double kSlack = 1e-6;
    const double tolerance = *surface_.tolerance;
    const PolygonLocator replaced(ReplacePolygons(features));
    const GridGeometry& g = dem.geometry();
    for (size_t t = 0; t < tin.triangles.size(); ++t) {
      if (!paint.visible[t]) continue;
      const TinTriangle& tri = tin.triangles[t];
      const CellTriangle cells =
          ToCellSpace(g, tin.vertices[tri.v[0]], tin.vertices[tri.v[1]], tin.vertices[tri.v[2]]);
      CellPlane plane;
      if (!PlaneOf(cells, &plane)) continue;
      double worst = tolerance + kSlack, worst_z = 0;
      int64_t worst_col = -1, worst_row = -1;
      float worst_dem = 0;
      ForEachCellSpan(cells, g.width, g.height, [&](int64_t r, int64_t first, int64_t last) {
        dem.ForEachCell(r, first, last, [&](int64_t c, float value) {
          if (std::isnan(value)) return;
          const double z = plane.At(static_cast<double>(c), static_cast<double>(r));
          const double error = std::fabs(z - value);
          if (error <= worst) return;
          if (!HoldsCellCentre(g, tin.vertices[tri.v[0]], tin.vertices[tri.v[1]],
                               tin.vertices[tri.v[2]], c, r))
            return;
          const Point2 centre{g.CellCenterX(c), g.CellCenterY(r)};
          if (!replaced.empty() && replaced.Locate(centre) != PointInPolygon::kOutside) return;
          if (!lines_.empty() && lines_.Near(centre, line_band_)) return;
          worst = error, worst_z = z, worst_col = c, worst_row = r, worst_dem = value;
        });
      });
      if (worst_col < 0) continue;
      char text[200];
      std::snprintf(text, sizeof text,
                    "|TIN - DEM| = %.6g m at the cell centre %s (TIN %.6g, DEM %.6g) exceeds the "
                    "tolerance %.6g m",
                    worst,
                    FormatPoint({g.CellCenterX(worst_col), g.CellCenterY(worst_row)}).c_str(),
                    worst_z, static_cast<double>(worst_dem), tolerance);
      Add("tolerance", ids[t], text);
    }
  }

  Store& store_;
  const SurfaceInfo& surface_;
  const bool full_;
  std::vector<Problem>* problems_;
  std::vector<int64_t> vertex_ids_;
  PagedIdMap<Point2> points_;
  std::unordered_set<int64_t> tag_ids_;                   // every id of tags
  std::vector<Row> rows_;                                 // by id
  PagedIdMap<uint32_t> index_;                            // triangle id -> index into rows_
  std::vector<std::pair<int64_t, int64_t>> constraints_;  // (min, max), sorted
  std::vector<HalfEdge> half_edges_;                      // sorted by (a, b), then triangle
  bool overused_ = false;
  LineElevation lines_;   // the surface's 3D lines (full check of a surface on a DEM)
  double line_band_ = 0;  // kLineBandCells in map units
};

}  // namespace

Result<std::vector<Problem>> CheckStore(Store& store, const CheckOptions& options) {
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  SurfaceStore surfaces(store);
  std::vector<SurfaceInfo> targets;
  if (options.surface) {
    TB_ASSIGN_OR_RETURN(SurfaceInfo one, surfaces.Find(*options.surface));
    targets.push_back(std::move(one));
  } else {
    TB_ASSIGN_OR_RETURN(targets, surfaces.List());
  }
  std::sort(targets.begin(), targets.end(),
            [](const SurfaceInfo& a, const SurfaceInfo& b) { return a.id < b.id; });
  std::vector<Problem> problems;
  for (const SurfaceInfo& surface : targets) {
    std::vector<Problem> found;
    TB_RETURN_IF_ERROR(SurfaceChecker(store, surface, options.full, &found).Run());
    // Surface-wide problems (no triangle) first, then by triangle; within a triangle, in the
    // order of the invariants.
    std::stable_sort(found.begin(), found.end(),
                     [](const Problem& a, const Problem& b) { return a.triangle < b.triangle; });
    problems.insert(problems.end(), found.begin(), found.end());
  }
  return problems;
}

}  // namespace tinbase
