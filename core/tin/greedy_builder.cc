#include "core/tin/greedy_builder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry/cdt.h"
#include "core/tin/cell_cover.h"
#include "core/tin/tolerance_refiner.h"

namespace tinbase {
namespace {

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

// The four grid corners (a corner on nodata takes the mean of its nearest valid cells), then
// tolerance refinement over the whole grid.
Tin BuildFromCorners(const Grid& dem, const GreedyOptions& options) {
  const GridGeometry& g = dem.geometry;
  std::vector<TinVertex> corners;
  for (auto [c, r] : {std::pair<int64_t, int64_t>{0, 0},
                      {g.width - 1, 0},
                      {0, g.height - 1},
                      {g.width - 1, g.height - 1}}) {
    const double z = dem.IsValid(c, r) ? dem.At(c, r) : MeanOfNearestValid(dem, c, r);
    corners.push_back(TinVertex{g.CellCenterX(c), g.CellCenterY(r), z, VertexKind::kDem});
  }
  Cdt cdt;
  cdt.InsertVertices(corners);  // distinct, so indices 0..3 in this order
  RefineOptions refine;
  refine.tolerance = options.tolerance;
  refine.max_points = options.max_points > 0 ? options.max_points - 4 : 0;
  if (options.max_points != 4) RefineToTolerance(cdt, dem, refine);
  Tin tin = cdt.ToTin();
  for (TinTriangle& t : tin.triangles) t.visible = TriangleOnData(dem, tin, t);
  return tin;
}

// Errors over every valid cell, each counted once, from the final triangles.
void Measure(const Grid& dem, const Tin& tin, GreedyReport* report) {
  const int64_t width = dem.geometry.width;
  std::vector<uint8_t> seen(dem.cells.size(), 0);
  double max_error = 0, sum_sq = 0;
  int64_t count = 0;
  for (const TinTriangle& t : tin.triangles) {
    const CellTriangle cells =
        ToCellSpace(dem.geometry, tin.vertices[t.v[0]], tin.vertices[t.v[1]], tin.vertices[t.v[2]]);
    CellPlane plane;
    if (!PlaneOf(cells, &plane)) continue;
    ForEachCellSpan(cells, width, dem.geometry.height, [&](int64_t r, int64_t first, int64_t last) {
      for (int64_t c = first; c <= last; ++c) {
        const size_t at = static_cast<size_t>(r * width + c);
        if (seen[at] || std::isnan(dem.cells[at])) continue;
        seen[at] = 1;
        const double error =
            std::fabs(plane.At(static_cast<double>(c), static_cast<double>(r)) - dem.cells[at]);
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

}  // namespace

Result<Tin> BuildGreedyTin(const Grid& dem, const GreedyOptions& options, GreedyReport* report) {
  TB_RETURN_IF_ERROR(Validate(dem, options));
  Tin tin = BuildFromCorners(dem, options);
  if (report != nullptr) Measure(dem, tin, report);
  return tin;
}

}  // namespace tinbase
