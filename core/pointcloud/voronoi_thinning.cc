#include "core/pointcloud/voronoi_thinning.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/geometry/cdt.h"
#include "core/pointcloud/plan_density.h"

namespace tinbase {
namespace {

Status ValidateOptions(const ThinningOptions& o) {
  if (!std::isfinite(o.vertical_threshold) || o.vertical_threshold < 0) {
    return Status::InvalidArgument("thinning: vertical threshold " +
                                   std::to_string(o.vertical_threshold) +
                                   " must be a finite value >= 0");
  }
  if (o.max_cell_area && !(std::isfinite(*o.max_cell_area) && *o.max_cell_area > 0)) {
    return Status::InvalidArgument("thinning: cell area threshold " +
                                   std::to_string(*o.max_cell_area) + " must be positive");
  }
  if (!(std::isfinite(o.median_fraction) && o.median_fraction > 0)) {
    return Status::InvalidArgument("thinning: median fraction " +
                                   std::to_string(o.median_fraction) + " must be positive");
  }
  if (o.window && !(std::isfinite(o.window->area) && o.window->area > 0)) {
    return Status::InvalidArgument("thinning: density window area " +
                                   std::to_string(o.window->area) + " must be positive");
  }
  if (o.window && !(std::isfinite(o.window->max_points) && o.window->max_points >= 0)) {
    return Status::InvalidArgument("thinning: density window count " +
                                   std::to_string(o.window->max_points) +
                                   " must be a finite value >= 0");
  }
  if (o.passes < 1) {
    return Status::InvalidArgument("thinning: passes " + std::to_string(o.passes) +
                                   " must be at least 1");
  }
  return Status::Ok();
}

Status ValidatePoints(const std::vector<TinVertex>& points) {
  for (size_t i = 0; i < points.size(); ++i) {
    const TinVertex& p = points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      return Status::InvalidArgument("point " + std::to_string(i) + ": x, y or z is not finite (" +
                                     std::to_string(p.x) + ", " + std::to_string(p.y) + ", " +
                                     std::to_string(p.z) + ")");
    }
  }
  return Status::Ok();
}

double MedianBoundedArea(const std::vector<VoronoiCell>& cells) {
  std::vector<double> areas;
  for (const VoronoiCell& c : cells) {
    if (c.bounded) areas.push_back(c.area);
  }
  if (areas.empty()) return 0;
  const auto mid = areas.begin() + static_cast<std::ptrdiff_t>(areas.size() / 2);
  std::nth_element(areas.begin(), mid, areas.end());
  return *mid;
}

// How far z strays from the neighbours under the chosen test (smaller is flatter).
double Deviation(const std::vector<TinVertex>& v, uint32_t i, const VoronoiCell& cell,
                 FlatnessTest test) {
  double worst = 0, sum = 0;
  for (uint32_t n : cell.neighbours) {
    worst = std::max(worst, std::abs(v[i].z - v[n].z));
    sum += v[n].z;
  }
  if (test == FlatnessTest::kAllNeighbours) return worst;
  return std::abs(v[i].z - sum / static_cast<double>(cell.neighbours.size()));
}

// Which vertices are in a dense cluster, by the window when there is one, else by cell area
// (setting *threshold from the cells when it is not yet known). Hull points never are.
std::vector<char> DenseVertices(const std::vector<TinVertex>& vertices,
                                const std::vector<VoronoiCell>& cells,
                                const ThinningOptions& options, std::optional<double>* threshold) {
  std::vector<char> dense(cells.size(), 0);
  if (options.window) {
    const double radius = std::sqrt(options.window->area / std::numbers::pi);
    const std::vector<uint32_t> counts = CountPointsWithinPlanRadius(vertices, radius);
    for (uint32_t i = 0; i < cells.size(); ++i) {
      dense[i] = cells[i].bounded && counts[i] > options.window->max_points;
    }
    return dense;
  }
  if (!*threshold) *threshold = options.median_fraction * MedianBoundedArea(cells);
  for (uint32_t i = 0; i < cells.size(); ++i) {
    dense[i] = cells[i].bounded && cells[i].area < **threshold;
  }
  return dense;
}

// One pass over `vertices` (distinct x, y): returns the positions to drop, no two of them
// Voronoi neighbours, and counts the dense vertices into *dense_count.
std::vector<uint32_t> ThinOnePass(const std::vector<TinVertex>& vertices,
                                  const ThinningOptions& options, std::optional<double>* threshold,
                                  size_t* dense_count) {
  Cdt cdt;
  cdt.InsertVertices(vertices);
  const std::vector<VoronoiCell> cells = cdt.VoronoiCells();
  const std::vector<char> dense = DenseVertices(vertices, cells, options, threshold);
  *dense_count = static_cast<size_t>(std::count(dense.begin(), dense.end(), 1));

  struct Candidate {
    double deviation;
    uint32_t vertex;
  };
  std::vector<Candidate> candidates;
  for (uint32_t i = 0; i < cells.size(); ++i) {
    const VoronoiCell& cell = cells[i];
    if (!dense[i] || cell.neighbours.empty()) continue;
    const double d = Deviation(vertices, i, cell, options.flatness);
    if (d <= options.vertical_threshold) candidates.push_back({d, i});
  }
  // Flattest first, so where two candidates are neighbours the more redundant one goes.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.deviation != b.deviation ? a.deviation < b.deviation : a.vertex < b.vertex;
  });
  std::vector<char> blocked(cells.size(), 0);
  std::vector<uint32_t> drop;
  for (const Candidate& c : candidates) {
    if (blocked[c.vertex]) continue;
    drop.push_back(c.vertex);
    blocked[c.vertex] = 1;
    for (uint32_t n : cells[c.vertex].neighbours) blocked[n] = 1;
  }
  std::sort(drop.begin(), drop.end());
  return drop;
}

}  // namespace

Result<ThinningResult> ThinByVoronoiDensity(const std::vector<TinVertex>& points,
                                            const ThinningOptions& options) {
  TB_RETURN_IF_ERROR(ValidateOptions(options));
  TB_RETURN_IF_ERROR(ValidatePoints(points));
  if (points.size() >= std::numeric_limits<uint32_t>::max()) {
    return Status::InvalidArgument("thinning: " + std::to_string(points.size()) +
                                   " points are more than one pass can index");
  }
  ThinningResult result;
  result.report.points_in = points.size();

  // The Cdt keeps the first of several points at one x, y and numbers vertices in input order,
  // so vertex k is the k-th distinct point.
  std::vector<uint32_t> input_of;  // input index of each distinct point
  {
    Cdt cdt;
    const std::vector<uint32_t> vertex_of = cdt.InsertVertices(points);
    for (uint32_t i = 0; i < vertex_of.size(); ++i) {
      if (vertex_of[i] == input_of.size()) input_of.push_back(i);
    }
  }
  result.report.duplicates = points.size() - input_of.size();

  std::optional<double> threshold = options.max_cell_area;
  std::vector<char> dropped(points.size(), 0);
  for (int pass = 0; pass < options.passes; ++pass) {
    std::vector<TinVertex> vertices;
    vertices.reserve(input_of.size());
    for (uint32_t i : input_of) vertices.push_back(points[i]);
    size_t dense = 0;
    const std::vector<uint32_t> drop = ThinOnePass(vertices, options, &threshold, &dense);
    if (pass == 0) result.report.dense = dense;
    if (drop.empty()) break;
    ++result.report.passes_run;
    for (uint32_t k : drop) dropped[input_of[k]] = 1;
    std::erase_if(input_of, [&](uint32_t i) { return dropped[i] != 0; });
  }

  result.kept = std::move(input_of);
  for (uint32_t i = 0; i < points.size(); ++i) {
    if (dropped[i]) result.dropped.push_back(i);
  }
  result.report.cell_area_threshold = options.window ? 0 : threshold.value_or(0);
  result.report.dropped = result.dropped.size();
  result.report.kept = result.kept.size();
  return result;
}

}  // namespace tinbase
