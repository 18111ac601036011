#include "core/tin/greedy_builder.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry/cdt.h"
#include "core/tin/cell_cover.h"
#include "core/tin/split_refinement.h"
#include "core/tin/tolerance_refiner.h"

namespace tinbase {
namespace {

// Mean of the valid cells in the smallest square window around (col, row) that holds any: the
// cells of the first ring of that window holding one, since the rings inside it hold none. NaN
// when the grid has no valid cell. REQUIRES: (col, row) is on the grid and nodata.
double MeanOfNearestValid(CellSource& dem, int64_t col, int64_t row) {
  const int64_t w = dem.geometry().width, h = dem.geometry().height;
  for (int64_t radius = 1; radius <= std::max(w, h); ++radius) {
    double sum = 0;
    int64_t count = 0;
    const auto add = [&](int64_t, float v) {
      if (std::isnan(v)) return;
      sum += v;
      ++count;
    };
    const int64_t c0 = std::max<int64_t>(0, col - radius), c1 = std::min(w - 1, col + radius);
    for (int64_t r = std::max<int64_t>(0, row - radius); r <= std::min(h - 1, row + radius); ++r) {
      if (r == row - radius || r == row + radius) {
        dem.ForEachCell(r, c0, c1, add);
        continue;
      }
      if (col - radius >= 0) add(col - radius, dem.At(col - radius, r));
      if (col + radius < w) add(col + radius, dem.At(col + radius, r));
    }
    if (count > 0) return sum / static_cast<double>(count);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

Status ValidateOptions(const GreedyOptions& options) {
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
  return Status::Ok();
}

Status ValidateGeometry(const GridGeometry& g) {
  if (g.width <= 0 || g.height <= 0) {
    return Status::InvalidArgument("greedy TIN: the DEM is empty (" + std::to_string(g.width) +
                                   " x " + std::to_string(g.height) + " cells)");
  }
  if (g.width < 2 || g.height < 2) {
    return Status::InvalidArgument("greedy TIN: the DEM needs at least 2 x 2 cells, got " +
                                   std::to_string(g.width) + " x " + std::to_string(g.height));
  }
  if (g.width > INT32_MAX || g.height > INT32_MAX) {
    return Status::InvalidArgument("greedy TIN: the DEM is too large (" + std::to_string(g.width) +
                                   " x " + std::to_string(g.height) + " cells)");
  }
  return Status::Ok();
}

// Valid cells every 2 * tile cells, inside the border: with them the first faces span a few
// tiles, not the whole grid, so refining a streamed DEM never scans a face larger than the
// block cache (each such scan would decode every block under it again). They cost a few
// points per 2 x 2 tiles where the terrain would not have needed them.
void AddSeedLattice(CellSource& dem, int64_t tile, std::vector<TinVertex>* vertices) {
  const GridGeometry& g = dem.geometry();
  const int64_t step = 2 * tile;
  for (int64_t r = step; r < g.height - 1; r += step) {
    for (int64_t c = step; c < g.width - 1; c += step) {
      const float z = dem.At(c, r);
      if (!std::isnan(z))
        vertices->push_back(TinVertex{g.CellCenterX(c), g.CellCenterY(r), z, VertexKind::kDem});
    }
  }
}

// The z a vertex on the grid's hull takes: the cell's value, or on nodata the mean of the valid
// cells nearest to it (NaN when the grid has none).
double HullElevation(CellSource& dem, int64_t col, int64_t row) {
  return dem.IsValid(col, row) ? dem.At(col, row) : MeanOfNearestValid(dem, col, row);
}

// The four grid corners, in the order the TIN lists them first. InvalidArgument when the grid
// has no valid cell.
Result<std::vector<TinVertex>> GridCorners(CellSource& dem) {
  const GridGeometry& g = dem.geometry();
  std::vector<TinVertex> corners;
  for (auto [c, r] : {std::pair<int64_t, int64_t>{0, 0},
                      {g.width - 1, 0},
                      {0, g.height - 1},
                      {g.width - 1, g.height - 1}}) {
    const double z = HullElevation(dem, c, r);
    if (std::isnan(z)) {
      TB_RETURN_IF_ERROR(dem.status());
      return Status::InvalidArgument("greedy TIN: the DEM has no valid cell (all nodata)");
    }
    corners.push_back(TinVertex{g.CellCenterX(c), g.CellCenterY(r), z, VertexKind::kDem});
  }
  return corners;
}

// The four grid corners, then tolerance refinement over the whole grid, unsplit.
Result<Tin> BuildFromCorners(CellSource& dem, const GreedyOptions& options) {
  TB_ASSIGN_OR_RETURN(std::vector<TinVertex> corners, GridCorners(dem));
  if (options.tile > 0) AddSeedLattice(dem, options.tile, &corners);
  Cdt cdt;
  cdt.InsertVertices(corners);  // distinct, so indices 0..3 are the corners in this order
  RefineOptions refine;
  refine.tolerance = options.tolerance;
  refine.max_points = options.max_points > 0 ? options.max_points - 4 : 0;
  refine.tile = options.tile;
  // Insertions are made in order; the largest scans are shared between threads.
  refine.parallel_scans = true;
  if (options.max_points != 4) RefineToTolerance(cdt, dem, refine);
  return cdt.ReleaseTin();
}

// Renumbers the vertices so that `first` (vertices of the TIN, by position) come first in that
// order, the others keeping theirs.
void PutFirst(const std::vector<TinVertex>& first, Tin& tin) {
  std::vector<uint32_t> new_index(tin.vertices.size(), UINT32_MAX);
  std::vector<TinVertex> ordered;
  ordered.reserve(tin.vertices.size());
  for (const TinVertex& want : first) {
    for (uint32_t i = 0; i < tin.vertices.size(); ++i) {
      if (tin.vertices[i].x != want.x || tin.vertices[i].y != want.y) continue;
      new_index[i] = static_cast<uint32_t>(ordered.size());
      ordered.push_back(tin.vertices[i]);
      break;
    }
  }
  for (uint32_t i = 0; i < tin.vertices.size(); ++i) {
    if (new_index[i] != UINT32_MAX) continue;
    new_index[i] = static_cast<uint32_t>(ordered.size());
    ordered.push_back(tin.vertices[i]);
  }
  tin.vertices = std::move(ordered);
  for (TinTriangle& t : tin.triangles)
    for (uint32_t& v : t.v) v = new_index[v];
}

// The TIN refined in two halves (core/tin/split_refinement.h); nullopt when `min_seam_vertices`
// keeps it unsplit.
Result<std::optional<Tin>> BuildInHalves(const Grid& dem, const GreedyOptions& options,
                                         size_t min_seam_vertices) {
  GridCellSource source(dem);
  TB_ASSIGN_OR_RETURN(std::vector<TinVertex> corners, GridCorners(source));
  std::optional<Cdt> cdt = RefineInHalves(
      dem, options.tolerance,
      [&](int64_t col, int64_t row) { return HullElevation(source, col, row); }, min_seam_vertices);
  if (!cdt) return std::optional<Tin>();
  Tin tin = cdt->ReleaseTin();
  // Nothing reads the triangulation any more: it is freed while PutFirst runs, which takes
  // about as long.
  tbb::parallel_invoke([&] { cdt.reset(); }, [&] { PutFirst(corners, tin); });
  return std::optional<Tin>(std::move(tin));
}

// Whether the options and the grid allow a split at all (its seam may still keep an automatic
// build unsplit).
bool MaySplit(const Grid& dem, const GreedyOptions& options) {
  if (options.split == GreedySplit::kNever || options.max_points > 0 || options.tile > 0)
    return false;
  const GridGeometry& g = dem.geometry;
  return options.split == GreedySplit::kAlways ? std::max(g.width, g.height) >= 3
                                               : WorthSplitting(g);
}

// The triangles in the order of the DEM tiles holding their centroids (256 cells: the DEM store's
// default block; any size near it gives the locality), so a pass over them reads the DEM nearly
// in order.
std::vector<size_t> InDemTileOrder(const GridGeometry& g, const Tin& tin) {
  const auto centroid = [&](size_t t) {
    const auto& v = tin.triangles[t].v;
    return std::pair{(tin.vertices[v[0]].x + tin.vertices[v[1]].x + tin.vertices[v[2]].x) / 3,
                     (tin.vertices[v[0]].y + tin.vertices[v[1]].y + tin.vertices[v[2]].y) / 3};
  };
  return InTileOrder(g, 256, tin.triangles.size(), centroid);
}

// Sets every triangle's visibility (on data or not), reading a streamed DEM in `order`.
void PaintInOrder(CellSource& dem, Tin& tin, const std::vector<size_t>& order) {
  for (size_t index : order) {
    TinTriangle& t = tin.triangles[index];
    t.visible = TriangleOnData(dem, tin, t);
  }
}

// |plane - DEM| over valid cells: the largest, the sum of squares and how many.
struct ErrorSums {
  double max_error = 0, sum_sq = 0;
  int64_t count = 0;
};

// The errors of the triangles, visited in `order`, over the valid cells of rows row_min..row_max,
// each cell counted once: `seen` holds a bit per cell (a cell on an edge is covered by both
// triangles; a bit, not a byte, as a streamed DEM may have billions of cells). Only the words of
// those rows' cells are touched, so row ranges that start at a multiple of 64 cells may be
// measured at once.
ErrorSums MeasureRows(CellSource& dem, const Tin& tin, const std::vector<size_t>& order,
                      int64_t row_min, int64_t row_max, std::vector<uint64_t>& seen) {
  const GridGeometry& g = dem.geometry();
  ErrorSums sums;
  for (size_t index : order) {
    const TinTriangle& t = tin.triangles[index];
    const CellTriangle cells =
        ToCellSpace(g, tin.vertices[t.v[0]], tin.vertices[t.v[1]], tin.vertices[t.v[2]]);
    const auto [first_row, last_row] = CellSpanRows(cells, g.height);
    if (last_row < row_min || first_row > row_max) continue;
    CellPlane plane;
    if (!PlaneOf(cells, &plane)) continue;
    ForEachCellSpanInRows(
        cells, g.width, g.height, row_min, row_max, [&](int64_t r, int64_t first, int64_t last) {
          dem.ForEachCell(r, first, last, [&](int64_t c, float value) {
            const auto at = static_cast<size_t>(r * g.width + c);
            const uint64_t bit = uint64_t{1} << (at % 64);
            if ((seen[at / 64] & bit) != 0 || std::isnan(value)) return;
            seen[at / 64] |= bit;
            const double error =
                std::fabs(plane.At(static_cast<double>(c), static_cast<double>(r)) - value);
            sums.max_error = std::max(sums.max_error, error);
            sums.sum_sq += error * error;
            ++sums.count;
          });
        });
  }
  return sums;
}

// The row near the middle of the grid whose first cell starts a word of MeasureRows' bits; 0
// when there is none short of the last row.
int64_t MiddleRowOnAWord(const GridGeometry& g) {
  for (int64_t row = g.height / 2; row < g.height; ++row)
    if ((row * g.width) % 64 == 0) return row;
  return 0;
}

// Fills `report` with the errors over every valid cell. On a DEM that allows concurrent reads
// the upper and lower halves of the rows are measured as two tasks (the measure is a sizeable
// part of a build); their sums are added in the same order on any number of threads.
void Measure(CellSource& dem, const Tin& tin, const std::vector<size_t>& order,
             GreedyReport* report) {
  const GridGeometry& g = dem.geometry();
  std::vector<uint64_t> seen(static_cast<size_t>((g.CellCount() + 63) / 64), 0);
  ErrorSums sums;
  const int64_t middle = MiddleRowOnAWord(g);
  if (dem.ConcurrentReads() && middle > 0) {
    ErrorSums lower;
    tbb::parallel_invoke([&] { sums = MeasureRows(dem, tin, order, 0, middle - 1, seen); },
                         [&] { lower = MeasureRows(dem, tin, order, middle, g.height - 1, seen); });
    sums.max_error = std::max(sums.max_error, lower.max_error);
    sums.sum_sq += lower.sum_sq;
    sums.count += lower.count;
  } else {
    sums = MeasureRows(dem, tin, order, 0, g.height - 1, seen);
  }
  report->max_error = sums.max_error;
  report->rms_error = sums.count > 0 ? std::sqrt(sums.sum_sq / static_cast<double>(sums.count)) : 0;
  report->points = static_cast<int64_t>(tin.vertices.size());
}

// Every triangle's visibility over a grid in memory: no reading order to keep, so no sort by
// tile. The triangles are marked in parallel: each one's flag depends on it alone.
void MarkVisible(const Grid& dem, Tin& tin) {
  // Every vertex is a cell centre, so every centroid lies on the grid, in a cell that holds data
  // when all do; ToTin left every triangle visible. Finding that out reads each cell once, far
  // less work than the test per triangle, which reads the cells under each.
  const bool any_nodata =
      std::any_of(dem.cells.begin(), dem.cells.end(), [](float v) { return std::isnan(v); });
  if (!any_nodata) return;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tin.triangles.size()),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t i = range.begin(); i != range.end(); ++i)
                        tin.triangles[i].visible = TriangleOnData(dem, tin, tin.triangles[i]);
                    });
}

}  // namespace

Result<Tin> BuildGreedyTin(CellSource& dem, const GreedyOptions& options, GreedyReport* report) {
  TB_RETURN_IF_ERROR(ValidateOptions(options));
  TB_RETURN_IF_ERROR(ValidateGeometry(dem.geometry()));
  TB_ASSIGN_OR_RETURN(Tin tin, BuildFromCorners(dem, options));
  const std::vector<size_t> order = InDemTileOrder(dem.geometry(), tin);
  PaintInOrder(dem, tin, order);
  if (report != nullptr) Measure(dem, tin, order, report);
  TB_RETURN_IF_ERROR(dem.status());
  return tin;
}

Result<Tin> BuildGreedyTin(const Grid& dem, const GreedyOptions& options, GreedyReport* report) {
  TB_RETURN_IF_ERROR(ValidateOptions(options));
  TB_RETURN_IF_ERROR(ValidateGeometry(dem.geometry));
  if (dem.cells.size() != static_cast<size_t>(dem.geometry.CellCount())) {
    return Status::InvalidArgument("greedy TIN: the DEM's cells do not match its " +
                                   std::to_string(dem.geometry.width) + " x " +
                                   std::to_string(dem.geometry.height) + " geometry");
  }
  GridCellSource source(dem);
  std::optional<Tin> halves;
  if (MaySplit(dem, options)) {
    TB_ASSIGN_OR_RETURN(halves, BuildInHalves(dem, options,
                                              options.split == GreedySplit::kAlways
                                                  ? size_t{0}
                                                  : MinSeamVertices(dem.geometry)));
  }
  Tin tin;
  if (halves) {
    tin = std::move(*halves);
  } else {
    TB_ASSIGN_OR_RETURN(tin, BuildFromCorners(source, options));
  }
  MarkVisible(dem, tin);
  if (report != nullptr) Measure(source, tin, InDemTileOrder(dem.geometry, tin), report);
  return tin;
}

}  // namespace tinbase
