#include "core/tin/rtin_builder.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <string>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

#include "core/tin/cell_lattice.h"

namespace tinbase {
namespace {

// A tree triangle in cell space: hypotenuse a-b, right angle at apex.
struct TreeTriangle {
  Cell a;
  Cell b;
  Cell apex;
};

// The midpoint of p-q when it is a lattice point.
bool LatticeMidpoint(Cell p, Cell q, Cell* mid) {
  if ((p.col + q.col) % 2 != 0 || (p.row + q.row) % 2 != 0) return false;
  *mid = Cell{(p.col + q.col) / 2, (p.row + q.row) / 2};
  return true;
}

// The smallest float not below e, so a stored error never understates the computed one.
float RoundUpToFloat(double e) {
  float f = static_cast<float>(e);
  if (static_cast<double>(f) < e) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

Status Validate(const Grid& dem, const RtinOptions& options) {
  if (!(options.tolerance >= 0) || !std::isfinite(options.tolerance)) {
    return Status::InvalidArgument(
        "RTIN: tolerance must be a finite, non-negative number of metres, got " +
        std::to_string(options.tolerance));
  }
  const GridGeometry& g = dem.geometry;
  if (g.width > kRtinMaxSide || g.height > kRtinMaxSide) {
    return Status::InvalidArgument("RTIN: the DEM's " + std::to_string(g.width) + " x " +
                                   std::to_string(g.height) + " cells exceed the " +
                                   std::to_string(kRtinMaxSide) +
                                   " cells a side one tree can hold; tile it first");
  }
  return ValidateLatticeGrid(dem, "RTIN");
}

// Runs first() on this thread and second() on another one when `parallel`, else both here, and
// returns when both are done; the two must write disjoint memory. If no thread can be started
// the work runs serially: the result never depends on the split. An exception from either
// (std::bad_alloc) reaches the caller once both have stopped.
template <typename First, typename Second>
void RunBoth(bool parallel, const First& first, const Second& second) {
  std::exception_ptr second_failed;
  {
    std::jthread other;  // joined on leaving the block, also when first() throws
    if (parallel) {
      try {
        other = std::jthread([&] {
          try {
            second();
          } catch (...) {
            second_failed = std::current_exception();
          }
        });
      } catch (const std::system_error&) {
        // No thread to be had (a resource limit): fall through to the serial path.
      }
    }
    if (!other.joinable()) second();
    first();
  }
  if (second_failed) std::rethrow_exception(second_failed);
}

// work(0) and work(1), as RunBoth.
template <typename Work>
void RunHalves(bool parallel, const Work& work) {
  RunBoth(
      parallel, [&work] { work(0); }, [&work] { work(1); });
}

// Every RTIN edge is axis-aligned or diagonal, so a vertex starts at most one half-edge in each
// of the eight lattice directions. Direction k points at 45 k degrees in cell space (0: +col,
// 2: +row); the twin of a half-edge in direction k runs in direction k + 4 (mod 8).
constexpr int kDirections = 8;
int Turn(int direction, int eighths) { return (direction + eighths) & (kDirections - 1); }

// Edge slots: one per vertex and direction 0-3; a slot holds the side of the edge that arrived
// first, then kPairedEdge.
constexpr int kEdgeSlotsPerVertex = 4;
constexpr uint32_t kNoEdge = 0xffffffff;
constexpr uint32_t kPairedEdge = 0xfffffffe;

class RtinBuilder {
 public:
  RtinBuilder(const Grid& dem, double tolerance)
      : dem_(dem),
        width_(static_cast<int32_t>(dem.geometry.width)),
        height_(static_cast<int32_t>(dem.geometry.height)),
        tolerance_(tolerance),
        has_nodata_(
            std::any_of(dem.cells.begin(), dem.cells.end(), [](float v) { return std::isnan(v); })),
        elevation_(dem) {
    span_ = 1;
    while (span_ < std::max(width_, height_) - 1) span_ *= 2;
    side_ = span_ + 1;
    parallel_ = int64_t{side_} * side_ >= kMinParallelLattice;
    padded_ = width_ != side_ || height_ != side_;
    // Not cleared: the error pass writes every lattice point but the four corners, which are no
    // diamond's centre and are never read. The first writes then fall to the two threads.
    const size_t lattice_points = static_cast<size_t>(side_) * static_cast<size_t>(side_);
    errors_ = std::make_unique_for_overwrite<float[]>(lattice_points);
    own_bounds_ = std::make_unique_for_overwrite<float[]>(lattice_points);
  }

  Tin Build(RtinReport* report) {
    ComputeDiamondErrors();
    CountTrianglesAndMarkVertices();
    Tin tin;
    AllocateAndNumberVertices(tin);
    EmitTriangles(tin);
    if (report != nullptr) {
      const CellFit fit = MeasureCellFit(dem_, tin);
      report->max_error = fit.max_error;
      report->rms_error = fit.rms_error;
      report->points = static_cast<int64_t>(tin.vertices.size());
      report->triangles = static_cast<int64_t>(tin.triangles.size());
      report->lattice_size = side_;
    }
    return tin;
  }

 private:
  // Below this many lattice points (a 257^2 lattice), starting a thread costs more than the
  // half of the work it takes over.
  static constexpr int64_t kMinParallelLattice = int64_t{257} * 257;

  size_t LatticeIndex(Cell c) const {
    return static_cast<size_t>(c.row) * static_cast<size_t>(side_) + static_cast<size_t>(c.col);
  }
  size_t CellIndex(Cell c) const {
    return static_cast<size_t>(c.row) * static_cast<size_t>(width_) + static_cast<size_t>(c.col);
  }
  float& ErrorAt(Cell c) { return errors_[LatticeIndex(c)]; }
  float& OwnBoundAt(Cell c) { return own_bounds_[LatticeIndex(c)]; }
  // The DEM's value; only for cells inside the grid that hold data.
  double Height(Cell c) const { return dem_.cells[CellIndex(c)]; }

  bool OnLattice(Cell c) const {
    return c.col >= 0 && c.row >= 0 && c.col <= span_ && c.row <= span_;
  }

  // Diamond centres level by level from the finest, so a diamond's children (whose centres are
  // the midpoints of its triangles' legs) are final before it reads them. At half-size h the
  // edge-centred diamonds (hypotenuse an axis-aligned edge of length 2h, apexes h away) come
  // first; their children are the square-centred diamonds of half-size h / 2. Then the
  // square-centred diamonds (hypotenuse a diagonal of a 2h square), whose children are the
  // edge-centred ones of half-size h.
  //
  // On two threads: a diamond reads only its descendants, whose centres lie at most `reach`
  // columns away (see ComputeLevels), so every level of the diamonds left of the middle column
  // by more than their reach is one thread's, those right of it the other's, with no
  // synchronisation between levels (which on a loaded machine costs more than the work). The
  // narrow cone around the middle column follows on one thread.
  void ComputeDiamondErrors() {
    const int32_t all = std::numeric_limits<int32_t>::max();
    if (!parallel_ || has_nodata_) {  // NodataElevation caches: one thread for nodata
      ComputeLevels([&](int32_t) { return ColumnRange{0, all}; });
      return;
    }
    const int32_t middle = span_ / 2;
    RunHalves(true, [&](int half) {
      ComputeLevels([&](int32_t reach) {
        return half == 0 ? ColumnRange{0, middle - 1 - reach}
                         : ColumnRange{middle + 1 + reach, all};
      });
    });
    ComputeLevels([&](int32_t reach) { return ColumnRange{middle - reach, middle + reach}; });
  }

  struct ColumnRange {
    int32_t first;
    int32_t last;  // inclusive
  };

  // Every level, each row restricted to the diamonds whose centre column lies in
  // columns(reach), reach being how far from its centre the centres of a diamond of the level
  // and of its descendants lie: 0 for edge-centred diamonds of half-size 1 (no children);
  // h + that of its edge-centred children for a square-centred diamond of half-size h; h / 2
  // + that of its square-centred children for an edge-centred one.
  template <typename ColumnsFn>
  void ComputeLevels(const ColumnsFn& columns) {
    int32_t edge_reach = 0;
    for (int32_t h = 1; h < span_; h *= 2) {
      const ColumnRange edge_columns = columns(edge_reach);
      for (int32_t y = 0; y <= span_; y += h) SetEdgeDiamondRow(y, h, edge_columns);
      const int32_t square_reach = h + edge_reach;
      const ColumnRange square_columns = columns(square_reach);
      for (int32_t y = h; y <= span_; y += 2 * h) SetSquareDiamondRow(y, h, square_columns);
      edge_reach = h + square_reach;
    }
  }

  // The first x >= range.first in the progression first_x, first_x + 2h, ...
  static int32_t FirstInRange(int32_t first_x, int32_t h, const ColumnRange& range) {
    if (range.first <= first_x) return first_x;
    const int32_t steps = (range.first - first_x + 2 * h - 1) / (2 * h);
    return first_x + steps * 2 * h;
  }

  void SetEdgeDiamondRow(int32_t y, int32_t h, const ColumnRange& range) {
    const bool vertical = (y / h) % 2 == 1;  // y an odd multiple of h, x an even one
    const int32_t last = std::min(span_, range.last);
    for (int32_t x = FirstInRange(vertical ? 0 : h, h, range); x <= last; x += 2 * h) {
      std::array<TreeTriangle, 2> pair;
      if (vertical) {  // apexes left and right
        pair = {TreeTriangle{{x, y - h}, {x, y + h}, {x - h, y}},
                TreeTriangle{{x, y + h}, {x, y - h}, {x + h, y}}};
      } else {  // apexes above and below
        pair = {TreeTriangle{{x + h, y}, {x - h, y}, {x, y - h}},
                TreeTriangle{{x - h, y}, {x + h, y}, {x, y + h}}};
      }
      SetDiamondError({x, y}, pair, h, /*finest=*/h == 1);
    }
  }

  void SetSquareDiamondRow(int32_t y, int32_t h, const ColumnRange& range) {
    const int32_t last = std::min(span_, range.last);
    for (int32_t x = FirstInRange(h, h, range); x <= last; x += 2 * h) {
      // The tree alternates the diagonals so that the four squares of a 2h x 2h block all
      // have a corner at the block's centre.
      const bool main_diagonal = ((x - h) / (2 * h) + (y - h) / (2 * h)) % 2 == 0;
      std::array<TreeTriangle, 2> pair;
      if (main_diagonal) {
        pair = {TreeTriangle{{x - h, y - h}, {x + h, y + h}, {x + h, y - h}},
                TreeTriangle{{x + h, y + h}, {x - h, y - h}, {x - h, y + h}}};
      } else {
        pair = {TreeTriangle{{x + h, y - h}, {x - h, y + h}, {x + h, y + h}},
                TreeTriangle{{x - h, y + h}, {x + h, y - h}, {x - h, y - h}}};
      }
      SetDiamondError({x, y}, pair, h, /*finest=*/false);
    }
  }

  void SetDiamondError(Cell centre, const std::array<TreeTriangle, 2>& pair, int32_t h,
                       bool finest) {
    if (IsInteriorOnData(centre, h)) {
      SetInteriorDiamondError(centre, pair, finest);
    } else {
      SetBorderDiamondError(centre, pair);
    }
  }

  // The diamond's square of half-size h around its centre lies in the grid, which holds no
  // nodata: both triangles exist and all their cells are data.
  bool IsInteriorOnData(Cell centre, int32_t h) const {
    return !has_nodata_ && centre.col >= h && centre.row >= h && centre.col + h < width_ &&
           centre.row + h < height_;
  }

  // SetBorderDiamondError's rules where nothing is missing: the two triangles share the
  // hypotenuse, hence the deviation d of the DEM at its midpoint from their planes; a finest
  // triangle's own error is d itself (its other cells are its corners).
  void SetInteriorDiamondError(Cell centre, const std::array<TreeTriangle, 2>& pair, bool finest) {
    const double z_mid = Height(centre);
    const double d = std::fabs((Height(pair[0].a) + Height(pair[0].b)) / 2 - z_mid);
    if (finest) {
      ErrorAt(centre) = OwnBoundAt(centre) = RoundUpToFloat(d);
      return;
    }
    float error = 0;
    float own = 0;
    for (const TreeTriangle& t : pair) {
      const Cell leg1{(t.apex.col + t.a.col) / 2, (t.apex.row + t.a.row) / 2};
      const Cell leg2{(t.b.col + t.apex.col) / 2, (t.b.row + t.apex.row) / 2};
      const float children = std::max(ErrorAt(leg1), ErrorAt(leg2));
      error = std::max(error, children);
      if (children > tolerance_) continue;  // the diamond splits whatever t's own error is
      const float t_own = RoundUpToFloat(
          OwnErrorFromDeviation(t, d, z_mid, std::max(OwnBoundAt(leg1), OwnBoundAt(leg2))));
      own = std::max(own, t_own);
      error = std::max(error, t_own);
    }
    ErrorAt(centre) = error;
    OwnBoundAt(centre) = own;
  }

  // A diamond's error: the worst of its (one or two) triangles' own errors and of its child
  // diamonds'. Only triangles whose apex is on the lattice exist. Select only asks whether it
  // exceeds the tolerance, so the stored value is exact only where that needs it: it is above
  // the tolerance exactly when the true error is, and when not above it is an upper bound of it.
  void SetBorderDiamondError(Cell centre, const std::array<TreeTriangle, 2>& pair) {
    float error = 0;
    float own = 0;  // its triangles' own errors (or bounds) alone
    for (const TreeTriangle& t : pair) {
      if (!OnLattice(t.apex)) continue;
      float children = 0;      // the child diamonds' errors
      float children_own = 0;  // bounds on the child triangles' own errors
      bool has_children = false;
      Cell child;
      for (const auto& [p, q] : {std::pair{t.apex, t.a}, std::pair{t.b, t.apex}}) {
        if (!LatticeMidpoint(p, q, &child)) continue;
        children = std::max(children, ErrorAt(child));
        children_own = std::max(children_own, OwnBoundAt(child));
        has_children = true;
      }
      error = std::max(error, children);
      if (children > tolerance_) continue;  // the diamond splits whatever t's own error is
      const float t_own = RoundUpToFloat(has_children ? OwnErrorOrBound(t, centre, children_own)
                                                      : LeafOwnError(t, centre));
      own = std::max(own, t_own);
      error = std::max(error, t_own);
    }
    ErrorAt(centre) = error;
    OwnBoundAt(centre) = own;
  }

  // OwnError of a finest triangle (hypotenuse two cells long, through cell m): it covers its
  // corners and m only, so those four are evaluated directly, the same way the scan would.
  double LeafOwnError(const TreeTriangle& t, Cell m) {
    if (!InsideOnData(t, m)) return OwnError(t);
    const std::array<Cell, 4> p = {t.a, t.b, t.apex, m};
    CellPlane plane;
    const bool planar =
        PlaneThrough({t.a, t.b, t.apex}, {Height(t.a), Height(t.b), Height(t.apex)}, &plane);
    assert(planar);
    (void)planar;
    double worst = 0;
    for (Cell c : p) worst = std::max(worst, std::fabs(plane.At(c.col, c.row) - Height(c)));
    return worst;
  }

  // t's own error, or a bound on the same side of the tolerance, without visiting t's cells
  // where the bounds decide (see OwnErrorFromDeviation).
  double OwnErrorOrBound(const TreeTriangle& t, Cell m, double children) {
    if (!InsideOnData(t, m)) return OwnError(t);
    // All four hold data, so their z is the DEM's. t's plane at the hypotenuse midpoint is the
    // mean of the hypotenuse's ends; with float inputs this d is exact in double.
    const double d = std::fabs((Height(t.a) + Height(t.b)) / 2 - Height(m));
    return OwnErrorFromDeviation(t, d, Height(m), children);
  }

  // t's children (split at the hypotenuse midpoint m, where the DEM is z_mid) interpolate the
  // DEM at m where t's plane is off by d; the two planes differ linearly, by at most d over
  // each child, so own(t) <= children + d, where `children` bounds the children's own errors.
  // And own(t) >= d since m holds data. Only between the two is every cell scanned.
  // REQUIRES: t and m inside the grid, on data.
  double OwnErrorFromDeviation(const TreeTriangle& t, double d, double z_mid, double children) {
    if (d > tolerance_) return d;
    // The margin covers the round-off of the plane evaluations that measure the true error.
    const double bound = children + d + 1e-9 * (1 + std::fabs(z_mid));
    if (bound <= tolerance_) return bound;
    return OwnError(t);
  }

  // t lies inside the grid and its corners and hypotenuse midpoint m hold data. Otherwise
  // OwnError's own checks apply (nodata corners take a costly nearest-valid mean).
  bool InsideOnData(const TreeTriangle& t, Cell m) const {
    if (!Inside(t)) return false;
    for (Cell c : {t.a, t.b, t.apex, m})
      if (!dem_.IsValid(c.col, c.row)) return false;
    return true;
  }

  bool Inside(const TreeTriangle& t) const {
    for (Cell c : {t.a, t.b, t.apex}) {
      if (c.col > width_ - 1 || c.row > height_ - 1) return false;
    }
    return true;
  }

  // Wholly outside the grid's rectangle of cell centres (touching its outline at most). The
  // padding lies right of and below the grid, so these are the only two ways.
  bool Outside(const TreeTriangle& t) const {
    return std::min(t.a.col, std::min(t.b.col, t.apex.col)) >= width_ - 1 ||
           std::min(t.a.row, std::min(t.b.row, t.apex.row)) >= height_ - 1;
  }

  // The largest |plane - DEM| over the valid cells the triangle covers: 0 outside the grid,
  // infinite across its outline (such a triangle must always be split).
  double OwnError(const TreeTriangle& t) {
    if (!Inside(t)) return Outside(t) ? 0 : std::numeric_limits<double>::infinity();
    const std::array<Cell, 3> p = {t.a, t.b, t.apex};
    const bool nodata_vertex =
        std::any_of(p.begin(), p.end(), [&](Cell c) { return !dem_.IsValid(c.col, c.row); });
    // A vertex on nodata needs the nearest valid cells' mean, which is costly deep inside a
    // void, so first make sure the triangle covers any data at all.
    if (nodata_vertex && !CoversValidCell(p)) return 0;
    CellPlane plane;
    const bool planar = PlaneThrough(p, {Z(t.a), Z(t.b), Z(t.apex)}, &plane);
    assert(planar);
    (void)planar;
    double worst = 0;
    const float* cells = dem_.cells.data();
    RasteriseTriangle(p, width_, height_, [&](int32_t r, int64_t first, int64_t last) {
      const float* row = cells + static_cast<int64_t>(r) * width_;
      for (int64_t c = first; c <= last; ++c) {
        const float value = row[c];
        if (std::isnan(value)) continue;
        worst = std::max(worst, std::fabs(plane.At(static_cast<double>(c), r) - value));
      }
    });
    return worst;
  }

  bool CoversValidCell(const std::array<Cell, 3>& p) const {
    bool any = false;
    RasteriseTriangle(p, width_, height_, [&](int32_t r, int64_t first, int64_t last) {
      for (int64_t c = first; c <= last && !any; ++c) any = dem_.IsValid(c, r);
    });
    return any;
  }

  // Not thread-safe (the nodata cache): only called on one thread when the grid has nodata.
  double Z(Cell c) { return elevation_.At(c.col, c.row); }

  // Pass 1 of the output: how many triangles each root triangle yields (each root on its own
  // thread), and which cells become vertices. Marks on the roots' shared diagonal may come from
  // both threads; they are equal.
  void CountTrianglesAndMarkVertices() {
    vertex_used_.assign(dem_.cells.size(), 0);
    RunHalves(parallel_, [&](int half) {
      int64_t count = 0;
      ForEachOutputTriangle(half, [&](const TreeTriangle& t, int) {
        ++count;
        for (Cell c : {t.a, t.b, t.apex}) {
          std::atomic_ref<uint8_t>(vertex_used_[CellIndex(c)]).store(1, std::memory_order_relaxed);
        }
      });
      triangle_count_[half] = count;
    });
  }

  // Calls output(t, direction of t's hypotenuse a -> b) for every triangle of the mesh under root
  // `half`, in tree order.
  template <typename OutputFn>
  void ForEachOutputTriangle(int half, const OutputFn& output) {
    const Cell origin{0, 0}, far{span_, span_};
    if (half == 0) {
      ForEachLeaf(origin, far, Cell{span_, 0}, 1, output);
    } else {
      ForEachLeaf(far, origin, Cell{0, span_}, 5, output);
    }
  }

  // Top-down: a triangle splits while its diamond's error exceeds the tolerance. Every tree
  // triangle (a, b, apex) turns clockwise in cell space, so with a -> b in direction k,
  // b -> apex runs in k + 5 and apex -> a in k + 3: the children's hypotenuses. Cells go by
  // value: this runs once per tree triangle, twice per build.
  template <typename OutputFn>
  void ForEachLeaf(Cell a, Cell b, Cell apex, int k, const OutputFn& output) {
    if (padded_ && Outside({a, b, apex})) return;
    // Only the unit triangles, whose hypotenuse is a cell diagonal (both coordinate sums odd),
    // have no midpoint on the lattice; they cannot split and lie wholly inside or outside.
    if (((a.col + b.col) & 1) == 0) {
      const Cell mid{(a.col + b.col) / 2, (a.row + b.row) / 2};
      if (ErrorAt(mid) > tolerance_) {
        ForEachLeaf(apex, a, mid, Turn(k, 3), output);
        ForEachLeaf(b, apex, mid, Turn(k, 5), output);
        return;
      }
    }
    assert(Inside({a, b, apex}));
    output(TreeTriangle{a, b, apex}, k);
  }

  // Vertices in row order on one thread while the other allocates the triangles and the edge
  // slots, whose sizes pass 1 fixed.
  void AllocateAndNumberVertices(Tin& tin) {
    const auto vertices =
        static_cast<size_t>(std::count(vertex_used_.begin(), vertex_used_.end(), uint8_t{1}));
    RunBoth(
        parallel_, [&] { NumberVertices(vertices, tin); },
        [&] {
          tin.triangles.resize(static_cast<size_t>(triangle_count_[0] + triangle_count_[1]));
          edge_slots_.assign(vertices * kEdgeSlotsPerVertex, kNoEdge);
        });
  }

  void NumberVertices(size_t vertices, Tin& tin) {
    vertex_of_ = std::make_unique_for_overwrite<uint32_t[]>(dem_.cells.size());
    tin.vertices.reserve(vertices);
    for (int32_t row = 0; row < height_; ++row) {
      for (int32_t col = 0; col < width_; ++col) {
        const Cell c{col, row};
        if (vertex_used_[CellIndex(c)] == 0) continue;
        vertex_of_[CellIndex(c)] = static_cast<uint32_t>(tin.vertices.size());
        tin.vertices.push_back(TinVertex{dem_.geometry.CellCenterX(col),
                                         dem_.geometry.CellCenterY(row),
                                         has_nodata_ ? Z(c) : Height(c), VertexKind::kDem});
      }
    }
  }

  // Pass 2: the triangles again, each root's into its own range of tin.triangles, linked to
  // their neighbours as the second side of each edge arrives. Edges on the roots' shared diagonal
  // are the only ones with a side in each thread; they are paired afterwards.
  void EmitTriangles(Tin& tin) {
    std::array<std::vector<EdgeSide>, 2> seam;
    RunHalves(parallel_, [&](int half) {
      auto index = static_cast<uint32_t>(half == 0 ? 0 : triangle_count_[0]);
      ForEachOutputTriangle(
          half, [&](const TreeTriangle& t, int k) { Emit(t, k, index++, tin, seam[half]); });
    });
    for (const auto& edges : seam) {
      for (const EdgeSide& e : edges) Pair(e, tin);
    }
  }

  // One side of an edge: the edge's slot and (triangle << 2) | index of the edge in it.
  struct EdgeSide {
    size_t slot;
    uint32_t side;
  };

  void Emit(const TreeTriangle& t, int k, uint32_t index, Tin& tin, std::vector<EdgeSide>& seam) {
    assert(int64_t{t.b.col - t.a.col} * (t.apex.row - t.a.row) -
               int64_t{t.apex.col - t.a.col} * (t.b.row - t.a.row) <
           0);
    // Cell space maps to the world by x ~ cell_x * col, y ~ cell_y * row: a north-up grid
    // (cell_y < 0) mirrors orientation, and turns the clockwise tree triangles counter-clockwise.
    const bool mirrored = (dem_.geometry.cell_x < 0) != (dem_.geometry.cell_y < 0);
    // The corners counter-clockwise in the world, and the direction of the edge from each.
    const std::array<Cell, 3> corners = {t.a, mirrored ? t.b : t.apex, mirrored ? t.apex : t.b};
    const std::array<int, 3> directions =
        mirrored ? std::array<int, 3>{k, Turn(k, 5), Turn(k, 3)}
                 : std::array<int, 3>{Turn(k, 7), Turn(k, 1), Turn(k, 4)};
    TinTriangle& tri = tin.triangles[index];
    for (int i = 0; i < 3; ++i) tri.v[i] = vertex_of_[CellIndex(corners[i])];
    // As HideNodataTriangles decides, from the cells at hand.
    if (has_nodata_) {
      const Cell centroid = CentroidCell(t.a, t.b, t.apex);
      tri.visible = dem_.IsValid(centroid.col, centroid.row);
    }
    for (int i = 0; i < 3; ++i) {
      // Edge i, opposite v[i], runs from corner i + 1 to corner i + 2.
      const int from = (i + 1) % 3, to = (i + 2) % 3;
      const EdgeSide e{EdgeSlot(tri.v[from], tri.v[to], directions[from]), (index << 2) | i};
      const bool on_seam =
          corners[from].col == corners[from].row && corners[to].col == corners[to].row;
      if (on_seam) {
        seam.push_back(e);
      } else {
        Pair(e, tin);
      }
    }
  }

  // An edge is filed under its end vertex that comes first in row order, where it leaves in one
  // of the directions 0 to 3 (east to south-west in cell space).
  static size_t EdgeSlot(uint32_t from, uint32_t to, int direction) {
    return direction < kEdgeSlotsPerVertex
               ? size_t{from} * kEdgeSlotsPerVertex + static_cast<size_t>(direction)
               : size_t{to} * kEdgeSlotsPerVertex + static_cast<size_t>(direction - 4);
  }

  // The first side of an edge to arrive waits in the slot; the second links the two triangles.
  void Pair(const EdgeSide& e, Tin& tin) {
    uint32_t& slot = edge_slots_[e.slot];
    assert(slot != kPairedEdge);  // else a third triangle on the edge: an overlap
    if (slot == kNoEdge) {
      slot = e.side;
      return;
    }
    tin.triangles[slot >> 2].n[slot & 3] = static_cast<int32_t>(e.side >> 2);
    tin.triangles[e.side >> 2].n[e.side & 3] = static_cast<int32_t>(slot >> 2);
    slot = kPairedEdge;
  }

  const Grid& dem_;
  const int32_t width_;
  const int32_t height_;
  const double tolerance_;
  const bool has_nodata_;
  NodataElevation elevation_;
  int32_t span_ = 1;                         // 2^k >= max(width, height) - 1
  int32_t side_ = 2;                         // span_ + 1
  bool parallel_ = false;                    // the lattice is large enough for two threads to pay
  bool padded_ = false;                      // the grid is smaller than the lattice
  std::unique_ptr<float[]> errors_;          // by diamond centre on the padded lattice
  std::unique_ptr<float[]> own_bounds_;      // likewise: bounds on its own triangles' errors only
  std::array<int64_t, 2> triangle_count_{};  // output triangles by root
  std::vector<uint8_t> vertex_used_;         // by cell: 1 where a triangle has a corner
  std::unique_ptr<uint32_t[]> vertex_of_;    // by cell: its vertex, where used
  std::vector<uint32_t> edge_slots_;         // by vertex and direction: see Pair
};

}  // namespace

Result<Tin> BuildRtinTin(const Grid& dem, const RtinOptions& options, RtinReport* report) {
  TB_RETURN_IF_ERROR(Validate(dem, options));
  RtinBuilder builder(dem, options.tolerance);
  return builder.Build(report);
}

}  // namespace tinbase
