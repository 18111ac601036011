// Cdt: the one adapter that owns CGAL's 2.5D constrained Delaunay triangulation.
//
// Every CGAL triangulation type of tinbase lives behind this class (STYLE.md, "Geometry"): the
// kernel is Epick, points are 3D but the triangulation is of their xy projection
// (Projection_traits_xy_3), and the intersection tag is Exact_predicates_tag, so constraints may
// cross (CGAL then inserts a vertex at the crossing). Vertices carry our index (their position in
// vertices()); faces carry a stamp that callers use for lazy invalidation of per-face work
// (CGAL recycles face memory, so a face reference alone does not say "same triangle").
//
// CGAL handles never leave this file pair: callers see vertex indices, TinVertex values and the
// opaque FaceRef, which is only meaningful to the Cdt that produced it.
//
// Ownership: a Cdt owns its triangulation and its copy of the vertices. Not synchronised; one
// thread at a time.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "core/tin/tin.h"
#include "core/tin/triangle_batch.h"

namespace tinbase {

// Elevation at a plan position, for vertices CGAL constructs (constraint crossings): their z comes
// from the DEM or a feature's level, never from CGAL's construction.
using ElevationFn = std::function<double(double x, double y)>;

// An opaque reference to a face of the Cdt that produced it. It stays a valid reference (to some
// face) for the life of the Cdt, because CGAL keeps face memory in a compact container and
// insertion by flips reuses faces; whether it is still the *same* triangle is what the stamp
// tells.
struct CdtFaceRef {
  void* opaque = nullptr;
};

// A vertex's Voronoi cell, read off the dual of the triangulation (paper 003 measures local
// point density by it).
struct VoronoiCell {
  bool bounded = false;              // false for a vertex on the convex hull: its cell is unbounded
  double area = 0;                   // plan area of the cell when bounded, else 0
  std::vector<uint32_t> neighbours;  // vertices sharing a triangulation edge, counter-clockwise
};

class Cdt {
 public:
  using FaceRef = CdtFaceRef;

  Cdt();
  ~Cdt();
  Cdt(Cdt&&) noexcept;
  Cdt& operator=(Cdt&&) noexcept;
  Cdt(const Cdt&) = delete;
  Cdt& operator=(const Cdt&) = delete;

  // Inserts `points` in one spatially sorted pass (CGAL's spatial_sort, then hinted insertion:
  // O(n log n) where one-by-one unhinted insertion is O(n^1.5)). Returns, for each input point
  // in order, the index of its vertex: a new one, or the existing one when a vertex with the same
  // x, y is already there (its z and kind are kept). New vertices get consecutive indices in
  // input order.
  std::vector<uint32_t> InsertVertices(const std::vector<TinVertex>& points);

  // Inserts `points` as InsertVertices does, in `bands` bands of increasing y (each spatially
  // sorted; band b ends after 1 - (1 - (b + 1) / bands)^2 of the points by y, so the bands shrink
  // upwards and the last, whose triangles a consumer can only have once all is done, holds
  // 1 / bands^2 of the points), and hands the triangulation to `finished` while it is built:
  // after each band, the finite triangles whose closed circumdisk lies strictly below every
  // point still to come (bounded in interval arithmetic, so the test errs only towards "not
  // yet"), which no later insertion can flip, and after the last band all the rest. Each batch
  // is sorted by `order` (ties in CGAL's face order) and numbered on from the last. Together the
  // batches are a Delaunay triangulation of the points, as ToTin's (co-circular points may take
  // the other diagonal).
  // Vertex indices are input positions (vertices() == points). The Cdt is left triangulated, but
  // ToTin renumbers its triangles. REQUIRES: the Cdt is empty; no two points share x, y;
  // bands >= 1.
  void InsertVerticesInBands(const std::vector<TinVertex>& points, int bands,
                             const TriangleOrder& order, const TriangleSink& finished);

  // Inserts one vertex, locating it by walking from `hint` (a face near the point; a default
  // FaceRef starts anywhere). Returns its index (an existing one on a duplicate x, y). Where the
  // new vertex is co-circular with an edge's two apices, the diagonal that was there is kept
  // (either is Delaunay): while there is no constraint by strict Lawson flips
  // (InsertUnconstrained in cdt.cc), after one by flipping CGAL's ties back
  // (KeepCocircularDiagonals; a chain of ties may then end with other diagonals inside the
  // co-circular polygon). When `incident` is not null it receives the finite faces the
  // insertion created or changed: those around the vertex, and those across an edge kept that
  // way.
  uint32_t InsertVertex(const TinVertex& point, FaceRef hint = {},
                        std::vector<FaceRef>* incident = nullptr);

  // Moves `other`'s vertices and faces into this triangulation, the two joined along the hull
  // edges they share, then flips every edge that is then not Delaunay until the whole is (an
  // edge is flipped only when the opposite vertex lies strictly inside the circle, so a
  // co-circular quad keeps the diagonal it had, as InsertVertex keeps it). For triangulations
  // built apart, e.g. on two threads, over regions that meet along a boundary. Returns, by
  // `other`'s vertex index, the index the vertex has here: a vertex on the shared boundary maps
  // to this one's vertex there (keeping this one's z and kind), the others get new indices
  // after this one's, in `other`'s order. When `changed` is not null it receives the finite
  // faces that have a vertex on the shared boundary or that a flip made; every other face is a
  // face of one of the two inputs, the same vertices in the same order. `other` is left empty.
  // REQUIRES: both have dimension 2 and no constraints; the hull edges of `other` whose two
  // vertices are hull vertices of this one too (same x, y) are hull edges of this one and form
  // the shared boundary; the two hulls' interiors are disjoint and their union is convex.
  std::vector<uint32_t> Absorb(Cdt&& other, std::vector<FaceRef>* changed = nullptr);

  // Constrains the segment between vertices a and b. Vertices lying on the segment split it;
  // crossings with other constraints create vertices whose index and z are assigned by
  // ToTin. REQUIRES: a, b < vertices().size() and a != b.
  void InsertConstraint(uint32_t a, uint32_t b);

  // Vertices that callers inserted, by index (constraint crossings are not among them until
  // ToTin has run).
  const std::vector<TinVertex>& vertices() const { return vertices_; }
  // Number of finite faces.
  size_t FaceCount() const;
  std::vector<FaceRef> FiniteFaces() const;

  // The indices of a finite face's vertices, counter-clockwise in plan view. REQUIRES: `face`
  // is finite and all its vertices have indices (no un-extracted constraint crossing).
  std::array<uint32_t, 3> FaceVertices(FaceRef face) const;
  // The same vertices with their positions (x, y, z as vertices() holds them), read from the
  // triangulation's own vertex records. For faces an insertion has just made those records are
  // in cache, where vertices()[index] is a random read: on a greedy build most of the scan of a
  // new face waited on those reads. REQUIRES: as FaceVertices.
  struct Corner {
    uint32_t index;
    double x, y, z;
  };
  std::array<Corner, 3> FaceCorners(FaceRef face) const;
  uint64_t FaceStamp(FaceRef face) const;
  void SetFaceStamp(FaceRef face, uint64_t stamp);

  // The Voronoi cell of every vertex, by index. The cell is the dual of the vertex's star, so it
  // is the true Voronoi cell only while no constraint has been inserted. REQUIRES: no
  // constraints; every vertex has an index (true without constraints).
  std::vector<VoronoiCell> VoronoiCells() const;

  // Gives every vertex CGAL created at a constraint crossing its index (after the existing ones,
  // kind kSteiner, z from `elevation`), so FaceVertices works on every face. ToTin does this
  // first too. REQUIRES: `elevation` callable when constraints crossed.
  void IndexCrossings(const ElevationFn& elevation);

  // The triangulation in our table layout: vertices in index order (vertices() first, then the
  // vertices CGAL created at constraint crossings, kind kSteiner, z from `elevation`), every
  // finite face as a counter-clockwise triangle with n[i] opposite v[i] (kNoNeighbour across the
  // convex hull), every constrained edge once in Tin::constraints, all triangles visible and
  // untagged. Crossing vertices keep the indices given here from then on. A large triangulation
  // is converted in parallel (TBB), to the same Tin on any number of threads.
  // REQUIRES: `elevation` callable when constraints crossed.
  Tin ToTin(const ElevationFn& elevation = nullptr);
  // ToTin for a triangulation that is discarded next: the vertex list is moved into the Tin
  // instead of copied, as that copy is part of a large build's peak memory. Afterwards
  // vertices() is empty and the Cdt may only be destroyed or assigned.
  Tin ReleaseTin(const ElevationFn& elevation = nullptr);

 private:
  Tin MakeTin(const ElevationFn& elevation, bool take_vertices);

  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<TinVertex> vertices_;
};

}  // namespace tinbase
