#include "core/tin/rtin_builder.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>
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

class RtinBuilder {
 public:
  RtinBuilder(const Grid& dem, double tolerance)
      : dem_(dem),
        width_(static_cast<int32_t>(dem.geometry.width)),
        height_(static_cast<int32_t>(dem.geometry.height)),
        tolerance_(tolerance),
        elevation_(dem) {
    span_ = 1;
    while (span_ < std::max(width_, height_) - 1) span_ *= 2;
    side_ = span_ + 1;
    errors_.assign(static_cast<size_t>(side_) * static_cast<size_t>(side_), 0.0f);
    own_bounds_.assign(errors_.size(), 0.0f);
  }

  Tin Build(RtinReport* report) {
    ComputeDiamondErrors();
    Tin tin;
    vertex_of_.assign(dem_.cells.size(), -1);
    const Cell origin{0, 0}, far{span_, span_};
    Select(TreeTriangle{origin, far, Cell{span_, 0}}, tin);
    Select(TreeTriangle{far, origin, Cell{0, span_}}, tin);
    [[maybe_unused]] const bool linked = LinkNeighbours(tin);
    assert(linked);
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
  float& ErrorAt(Cell c) {
    return errors_[static_cast<size_t>(c.row) * static_cast<size_t>(side_) +
                   static_cast<size_t>(c.col)];
  }
  float& OwnBoundAt(Cell c) {
    return own_bounds_[static_cast<size_t>(c.row) * static_cast<size_t>(side_) +
                       static_cast<size_t>(c.col)];
  }

  bool OnLattice(Cell c) const {
    return c.col >= 0 && c.row >= 0 && c.col <= span_ && c.row <= span_;
  }

  // Diamond centres level by level from the finest, so a diamond's children (whose centres are
  // the midpoints of its triangles' legs) are final before it reads them. At half-size h the
  // edge-centred diamonds (hypotenuse an axis-aligned edge of length 2h, apexes h away) come
  // first; their children are the square-centred diamonds of half-size h / 2. Then the
  // square-centred diamonds (hypotenuse a diagonal of a 2h square), whose children are the
  // edge-centred ones of half-size h.
  void ComputeDiamondErrors() {
    for (int32_t h = 1; h < span_; h *= 2) {
      for (int32_t y = 0; y <= span_; y += h) {
        const bool y_odd = (y / h) % 2 == 1;
        for (int32_t x = y_odd ? 0 : h; x <= span_; x += 2 * h) {
          // One coordinate an odd multiple of h, the other an even one: an edge centre.
          const Cell m{x, y};
          std::array<TreeTriangle, 2> pair;
          if (y_odd) {  // vertical hypotenuse, apexes left and right
            pair = {TreeTriangle{{x, y - h}, {x, y + h}, {x - h, y}},
                    TreeTriangle{{x, y + h}, {x, y - h}, {x + h, y}}};
          } else {  // horizontal hypotenuse, apexes above and below
            pair = {TreeTriangle{{x + h, y}, {x - h, y}, {x, y - h}},
                    TreeTriangle{{x - h, y}, {x + h, y}, {x, y + h}}};
          }
          SetDiamondError(m, pair);
        }
      }
      for (int32_t y = h; y <= span_; y += 2 * h) {
        for (int32_t x = h; x <= span_; x += 2 * h) {
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
          SetDiamondError({x, y}, pair);
        }
      }
    }
  }

  // A diamond's error: the worst of its (one or two) triangles' own errors and of its child
  // diamonds'. Only triangles whose apex is on the lattice exist. Select only asks whether it
  // exceeds the tolerance, so the stored value is exact only where that needs it: it is above
  // the tolerance exactly when the true error is, and when not above it is an upper bound of it.
  void SetDiamondError(Cell centre, const std::array<TreeTriangle, 2>& pair) {
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
    const auto z = [&](Cell c) -> double { return dem_.At(c.col, c.row); };
    CellPlane plane;
    const bool planar = PlaneThrough({t.a, t.b, t.apex}, {z(t.a), z(t.b), z(t.apex)}, &plane);
    assert(planar);
    (void)planar;
    double worst = 0;
    for (Cell c : p) worst = std::max(worst, std::fabs(plane.At(c.col, c.row) - z(c)));
    return worst;
  }

  // t's own error, or a bound on the same side of the tolerance, without visiting t's cells
  // where the bounds decide. t's children (split at the hypotenuse midpoint m) interpolate the
  // DEM at m where t's plane is off by d; the two planes differ linearly, by at most d over
  // each child, so own(t) <= children + d, where `children` bounds the children's own errors. And
  // own(t) >= d when m holds data. Only between the two is every cell scanned.
  double OwnErrorOrBound(const TreeTriangle& t, Cell m, double children) {
    if (!InsideOnData(t, m)) return OwnError(t);
    // All four hold data, so their z is the DEM's. t's plane at the hypotenuse midpoint is the
    // mean of the hypotenuse's ends; with float inputs this d is exact in double.
    const auto z = [&](Cell c) -> double { return dem_.At(c.col, c.row); };
    const double d = std::fabs((z(t.a) + z(t.b)) / 2 - z(m));
    if (d > tolerance_) return d;
    // The margin covers the round-off of the plane evaluations that measure the true error.
    const double bound = children + d + 1e-9 * (1 + std::fabs(z(m)));
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
    return std::min({t.a.col, t.b.col, t.apex.col}) >= width_ - 1 ||
           std::min({t.a.row, t.b.row, t.apex.row}) >= height_ - 1;
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

  double Z(Cell c) { return elevation_.At(c.col, c.row); }

  // Top-down: a triangle splits while its diamond's error exceeds the tolerance. The unit
  // triangles (hypotenuse a cell diagonal) cannot split and lie wholly inside or outside.
  void Select(const TreeTriangle& t, Tin& tin) {
    if (Outside(t)) return;
    Cell mid;
    if (LatticeMidpoint(t.a, t.b, &mid) && ErrorAt(mid) > tolerance_) {
      Select(TreeTriangle{t.apex, t.a, mid}, tin);
      Select(TreeTriangle{t.b, t.apex, mid}, tin);
      return;
    }
    assert(Inside(t));
    Emit(t, tin);
  }

  void Emit(const TreeTriangle& t, Tin& tin) {
    // Cell space maps to the world by x ~ cell_x * col, y ~ cell_y * row: a north-up grid
    // (cell_y < 0) mirrors orientation.
    const int64_t cross = int64_t{t.b.col - t.a.col} * (t.apex.row - t.a.row) -
                          int64_t{t.apex.col - t.a.col} * (t.b.row - t.a.row);
    const bool mirrored = (dem_.geometry.cell_x < 0) != (dem_.geometry.cell_y < 0);
    const bool ccw = (cross > 0) != mirrored;
    TinTriangle tri;
    tri.v = {VertexIndex(t.a, tin), VertexIndex(ccw ? t.b : t.apex, tin),
             VertexIndex(ccw ? t.apex : t.b, tin)};
    // As HideNodataTriangles decides, from the cells at hand.
    const Cell centroid = CentroidCell(t.a, t.b, t.apex);
    tri.visible = dem_.IsValid(centroid.col, centroid.row);
    tin.triangles.push_back(tri);
  }

  uint32_t VertexIndex(Cell c, Tin& tin) {
    int32_t& index = vertex_of_[static_cast<size_t>(c.row) * static_cast<size_t>(width_) +
                                static_cast<size_t>(c.col)];
    if (index < 0) {
      index = static_cast<int32_t>(tin.vertices.size());
      tin.vertices.push_back(TinVertex{dem_.geometry.CellCenterX(c.col),
                                       dem_.geometry.CellCenterY(c.row), Z(c), VertexKind::kDem});
    }
    return static_cast<uint32_t>(index);
  }

  const Grid& dem_;
  const int32_t width_;
  const int32_t height_;
  const double tolerance_;
  NodataElevation elevation_;
  int32_t span_ = 1;                // 2^k >= max(width, height) - 1
  int32_t side_ = 2;                // span_ + 1
  std::vector<float> errors_;       // by diamond centre on the padded lattice
  std::vector<float> own_bounds_;   // likewise: bounds on its own triangles' errors only
  std::vector<int32_t> vertex_of_;  // by cell, -1 until emitted
};

}  // namespace

Result<Tin> BuildRtinTin(const Grid& dem, const RtinOptions& options, RtinReport* report) {
  TB_RETURN_IF_ERROR(Validate(dem, options));
  RtinBuilder builder(dem, options.tolerance);
  return builder.Build(report);
}

}  // namespace tinbase
