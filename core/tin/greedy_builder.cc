#include "core/tin/greedy_builder.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <queue>
#include <string>
#include <vector>

#include "core/geometry/cdt.h"

namespace tinbase {
namespace {

// Grid cells are addressed in "cell space": the centre of cell (col, row) is the integer point
// (col, row). World coordinates are an axis-aligned affine image of it, so planes, containment
// and barycentric values agree in both; cell space makes the rasterisation exact.
struct Cell {
  int32_t col = 0;
  int32_t row = 0;
};

// z = z0 + a (col - c0) + b (row - r0) through a triangle's three vertices.
struct Plane {
  double a = 0;
  double b = 0;
  double z0 = 0;
  int32_t c0 = 0;
  int32_t r0 = 0;
  double At(double col, double row) const { return z0 + a * (col - c0) + b * (row - r0); }
};

// False for a triangle of zero area in cell space (it covers no cell centre of its own).
bool PlaneThrough(const std::array<Cell, 3>& p, const std::array<double, 3>& z, Plane* plane) {
  const double dc1 = p[1].col - p[0].col, dr1 = p[1].row - p[0].row;
  const double dc2 = p[2].col - p[0].col, dr2 = p[2].row - p[0].row;
  const double det = dc1 * dr2 - dc2 * dr1;
  if (det == 0) return false;
  const double dz1 = z[1] - z[0], dz2 = z[2] - z[0];
  plane->a = (dz1 * dr2 - dz2 * dr1) / det;
  plane->b = (dc1 * dz2 - dc2 * dz1) / det;
  plane->z0 = z[0];
  plane->c0 = p[0].col;
  plane->r0 = p[0].row;
  return true;
}

// Calls span(row, first_col, last_col) for every row of cell centres inside or on the triangle,
// clipped to the grid. Edge crossings are exact rationals of small integers, so the tiny margin
// only absorbs the division's rounding.
template <typename SpanFn>
void RasteriseTriangle(const std::array<Cell, 3>& p, int64_t width, int64_t height, SpanFn&& span) {
  const int32_t row_min = std::max<int32_t>(0, std::min({p[0].row, p[1].row, p[2].row}));
  const int32_t row_max =
      std::min<int32_t>(static_cast<int32_t>(height - 1), std::max({p[0].row, p[1].row, p[2].row}));
  for (int32_t r = row_min; r <= row_max; ++r) {
    double left = std::numeric_limits<double>::infinity();
    double right = -left;
    for (int e = 0; e < 3; ++e) {
      const Cell& a = p[e];
      const Cell& b = p[(e + 1) % 3];
      if (r < std::min(a.row, b.row) || r > std::max(a.row, b.row)) continue;
      if (a.row == b.row) {
        left = std::min({left, double(a.col), double(b.col)});
        right = std::max({right, double(a.col), double(b.col)});
        continue;
      }
      const double x = a.col + double(r - a.row) * double(b.col - a.col) / double(b.row - a.row);
      left = std::min(left, x);
      right = std::max(right, x);
    }
    const int64_t first = std::max<int64_t>(0, static_cast<int64_t>(std::ceil(left - 1e-9)));
    const int64_t last =
        std::min<int64_t>(width - 1, static_cast<int64_t>(std::floor(right + 1e-9)));
    if (first <= last) span(r, first, last);
  }
}

bool IsVertexOf(const std::array<Cell, 3>& p, int64_t col, int32_t row) {
  for (const Cell& v : p) {
    if (v.col == col && v.row == row) return true;
  }
  return false;
}

// Mean of the valid cells in the smallest square window around (col, row) that holds any.
// REQUIRES: the grid has a valid cell.
double MeanOfNearestValid(const Grid& dem, int64_t col, int64_t row) {
  const int64_t w = dem.geometry.width, h = dem.geometry.height;
  for (int64_t radius = 1;; ++radius) {
    double sum = 0;
    int64_t count = 0;
    for (int64_t r = std::max<int64_t>(0, row - radius); r <= std::min(h - 1, row + radius); ++r) {
      for (int64_t c = std::max<int64_t>(0, col - radius); c <= std::min(w - 1, col + radius);
           ++c) {
        if (dem.IsValid(c, r)) {
          sum += dem.At(c, r);
          ++count;
        }
      }
    }
    if (count > 0) return sum / static_cast<double>(count);
  }
}

Status Validate(const Grid& dem, const GreedyOptions& options) {
  const GridGeometry& g = dem.geometry;
  if (!(options.tolerance > 0) || !std::isfinite(options.tolerance)) {
    return Status::InvalidArgument(
        "greedy TIN: tolerance must be a positive number of metres, got " +
        std::to_string(options.tolerance));
  }
  if (options.max_points < 0 || (options.max_points > 0 && options.max_points < 4)) {
    return Status::InvalidArgument(
        "greedy TIN: max_points must be 0 (no limit) or at least 4 (the grid corners), got " +
        std::to_string(options.max_points));
  }
  if (g.width <= 0 || g.height <= 0) {
    return Status::InvalidArgument("greedy TIN: the DEM is empty (" + std::to_string(g.width) +
                                   " x " + std::to_string(g.height) + " cells)");
  }
  if (g.width < 2 || g.height < 2) {
    return Status::InvalidArgument("greedy TIN: the DEM needs at least 2 x 2 cells, got " +
                                   std::to_string(g.width) + " x " + std::to_string(g.height));
  }
  if (g.width > INT32_MAX || g.height > INT32_MAX ||
      dem.cells.size() != static_cast<size_t>(g.CellCount())) {
    return Status::InvalidArgument("greedy TIN: the DEM's cells do not match its " +
                                   std::to_string(g.width) + " x " + std::to_string(g.height) +
                                   " geometry");
  }
  if (std::none_of(dem.cells.begin(), dem.cells.end(), [](float v) { return !std::isnan(v); })) {
    return Status::InvalidArgument("greedy TIN: the DEM has no valid cell (all nodata)");
  }
  return Status::Ok();
}

class GreedyBuilder {
 public:
  GreedyBuilder(const Grid& dem, const GreedyOptions& options)
      : dem_(dem), tolerance_(options.tolerance), max_points_(options.max_points) {}

  Tin Build(GreedyReport* report) {
    InsertCorners();
    for (Cdt::FaceRef f : cdt_.FiniteFaces()) Scan(f);
    std::vector<Cdt::FaceRef> incident;
    while (!queue_.empty()) {
      if (max_points_ > 0 && static_cast<int64_t>(cells_.size()) >= max_points_) break;
      const Candidate worst = queue_.top();
      queue_.pop();
      if (cdt_.FaceStamp(worst.face) != worst.stamp) continue;  // face changed since its scan
      InsertCell(worst.cell, worst.face, &incident);
      for (Cdt::FaceRef f : incident) Scan(f);
    }
    Tin tin = cdt_.ToTin();
    MarkNodataInvisible(tin);
    if (report != nullptr) Measure(tin, report);
    return tin;
  }

 private:
  struct Candidate {
    double error;
    Cdt::FaceRef face;
    uint64_t stamp;
    Cell cell;
    bool operator<(const Candidate& o) const { return error < o.error; }
  };

  TinVertex VertexAt(Cell cell, double z) const {
    return TinVertex{dem_.geometry.CellCenterX(cell.col), dem_.geometry.CellCenterY(cell.row), z,
                     VertexKind::kDem};
  }

  void InsertCorners() {
    const int32_t last_col = static_cast<int32_t>(dem_.geometry.width - 1);
    const int32_t last_row = static_cast<int32_t>(dem_.geometry.height - 1);
    std::vector<TinVertex> corners;
    for (Cell c : {Cell{0, 0}, Cell{last_col, 0}, Cell{0, last_row}, Cell{last_col, last_row}}) {
      const double z = dem_.IsValid(c.col, c.row) ? dem_.At(c.col, c.row)
                                                  : MeanOfNearestValid(dem_, c.col, c.row);
      corners.push_back(VertexAt(c, z));
      cells_.push_back(c);
    }
    cdt_.InsertVertices(corners);  // distinct, so indices 0..3 in this order
  }

  void InsertCell(Cell cell, Cdt::FaceRef hint, std::vector<Cdt::FaceRef>* incident) {
    const uint32_t index =
        cdt_.InsertVertex(VertexAt(cell, dem_.At(cell.col, cell.row)), hint, incident);
    // A worst sample is off the surface by more than the tolerance, so it is never a vertex yet.
    assert(index == cells_.size());
    (void)index;
    cells_.push_back(cell);
  }

  // Gives the face a fresh stamp (invalidating its older queue entries) and queues its worst
  // valid sample if that is beyond the tolerance.
  void Scan(Cdt::FaceRef face) {
    const uint64_t stamp = next_stamp_++;
    cdt_.SetFaceStamp(face, stamp);
    const std::array<uint32_t, 3> v = cdt_.FaceVertices(face);
    const std::array<Cell, 3> p = {cells_[v[0]], cells_[v[1]], cells_[v[2]]};
    Plane plane;
    if (!PlaneThrough(p, {vz(v[0]), vz(v[1]), vz(v[2])}, &plane)) return;
    double worst = tolerance_;
    Cell worst_cell;
    bool found = false;
    const float* cells = dem_.cells.data();
    const int64_t width = dem_.geometry.width;
    RasteriseTriangle(p, width, dem_.geometry.height, [&](int32_t r, int64_t first, int64_t last) {
      const float* row = cells + static_cast<int64_t>(r) * width;
      double z = plane.At(static_cast<double>(first), r);
      for (int64_t c = first; c <= last; ++c, z += plane.a) {
        const float value = row[c];
        if (std::isnan(value)) continue;
        const double error = std::fabs(z - value);
        // The plane passes through the face's own vertices only up to round-off; with a tiny
        // tolerance that noise must not pick a vertex again (checked only on a new maximum).
        if (error > worst && !IsVertexOf(p, c, r)) {
          worst = error;
          worst_cell = Cell{static_cast<int32_t>(c), r};
          found = true;
        }
      }
    });
    if (found) queue_.push(Candidate{worst, face, stamp, worst_cell});
  }

  double vz(uint32_t index) const { return cdt_.vertices()[index].z; }

  // A triangle whose centroid lies on a nodata cell is not part of the surface.
  void MarkNodataInvisible(Tin& tin) const {
    for (TinTriangle& t : tin.triangles) {
      double col = 0, row = 0;
      for (uint32_t i : t.v) {
        col += cells_[i].col;
        row += cells_[i].row;
      }
      const int64_t c = std::clamp<int64_t>(std::llround(col / 3), 0, dem_.geometry.width - 1);
      const int64_t r = std::clamp<int64_t>(std::llround(row / 3), 0, dem_.geometry.height - 1);
      t.visible = dem_.IsValid(c, r);
    }
  }

  // Errors over every valid cell, each counted once, from the final triangles.
  void Measure(const Tin& tin, GreedyReport* report) const {
    const int64_t width = dem_.geometry.width;
    std::vector<uint8_t> seen(dem_.cells.size(), 0);
    double max_error = 0, sum_sq = 0;
    int64_t count = 0;
    for (const TinTriangle& t : tin.triangles) {
      const std::array<Cell, 3> p = {cells_[t.v[0]], cells_[t.v[1]], cells_[t.v[2]]};
      Plane plane;
      if (!PlaneThrough(p, {vz(t.v[0]), vz(t.v[1]), vz(t.v[2])}, &plane)) continue;
      RasteriseTriangle(
          p, width, dem_.geometry.height, [&](int32_t r, int64_t first, int64_t last) {
            for (int64_t c = first; c <= last; ++c) {
              const size_t at = static_cast<size_t>(r * width + c);
              if (seen[at] || std::isnan(dem_.cells[at])) continue;
              seen[at] = 1;
              const double error = std::fabs(plane.At(static_cast<double>(c), r) - dem_.cells[at]);
              max_error = std::max(max_error, error);
              sum_sq += error * error;
              ++count;
            }
          });
    }
    report->max_error = max_error;
    report->rms_error = count > 0 ? std::sqrt(sum_sq / static_cast<double>(count)) : 0;
    report->points = static_cast<int64_t>(tin.vertices.size());
  }

  const Grid& dem_;
  const double tolerance_;
  const int64_t max_points_;
  Cdt cdt_;
  std::vector<Cell> cells_;  // by vertex index
  std::priority_queue<Candidate> queue_;
  uint64_t next_stamp_ = 1;  // 0 is a fresh face's stamp, never queued
};

}  // namespace

Result<Tin> BuildGreedyTin(const Grid& dem, const GreedyOptions& options, GreedyReport* report) {
  TB_RETURN_IF_ERROR(Validate(dem, options));
  GreedyBuilder builder(dem, options);
  return builder.Build(report);
}

}  // namespace tinbase
