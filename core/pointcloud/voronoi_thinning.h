// VoronoiThinning: drops redundant LiDAR points in dense, flat clusters (paper 003, Lake Erie).
//
// The method, per pass:
//  1. Delaunay-triangulate the points; the dual gives each point's Voronoi cell and neighbours.
//  2. A point is in a dense cluster when its cell is bounded (points on the convex hull are never
//     dropped, so the domain keeps its outline) and the cloud is dense around it. Density is
//     judged one of two ways. By cell area: the cell is smaller than a threshold (the paper's
//     "no more than 10 Voronoi polygons per 150 square feet" read as 15 ft² per cell); by default
//     the threshold is `median_fraction` of the median bounded cell area of the input, so only
//     clusters clearly denser than the cloud's typical spacing (pass edges and overlaps in the
//     paper) qualify, and a uniformly dense cloud is left alone. Or by a density window, the
//     paper's words taken literally: more than `max_points` points lie in the disc of `area`
//     around the point (counted with OpenVDB, core/pointcloud/plan_density.h). The window
//     looks past a point's own cell, so a single close pair in sparse ground is not a cluster.
//  3. A dense point is redundant when its z is within `vertical_threshold` of its Voronoi
//     neighbours. The paper says only "points in the same proximity ... that have elevations
//     within a threshold"; the default here is the strict reading, within the threshold of *every*
//     neighbour (kAllNeighbours); kNeighbourMean compares with their mean instead.
//  4. Redundant points are dropped flattest first, and never two Voronoi neighbours in one pass.
//     Because of that each dropped point's neighbours all survive, and removing a vertex from a
//     Delaunay triangulation only re-triangulates its star, so the thinned TIN at a dropped point
//     interpolates only its old neighbours: with kAllNeighbours it passes within
//     `vertical_threshold` of every point dropped in the pass. That is what keeps the result
//     faithful, and what the paper's "Voronoi tree" update (its step d) achieves.
// Further passes (`passes` > 1) repeat 1-4 on the survivors with the first pass's area threshold;
// the bound then loosens to passes x vertical_threshold for points dropped in early passes (a
// later pass may drop a neighbour they were interpolated from).
//
// Input points with the same x, y as an earlier one are duplicates: the first is kept, the rest
// are counted and never appear in the output. Stateless; thread-safe.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/base/status.h"
#include "core/tin/tin.h"

namespace tinbase {

enum class FlatnessTest {
  kAllNeighbours,  // |z - z_n| <= threshold for every Voronoi neighbour n
  kNeighbourMean,  // |z - mean(z_n)| <= threshold
};

// "No more than max_points points per area": a point is dense when more than max_points points
// (itself included) lie within the disc of this area centred on it.
struct DensityWindow {
  double max_points = 10;
  double area = 150;
};

struct ThinningOptions {
  // When set, density is judged by this window and the cell-area threshold below is unused.
  std::optional<DensityWindow> window;
  // Cells with an area below this (in squared plan units) are dense. When unset, the threshold
  // is median_fraction times the median bounded cell area of the input.
  std::optional<double> max_cell_area;
  double median_fraction = 0.75;
  // In z units (the paper: 0.15 ft for points of 570-572 ft).
  double vertical_threshold = 0.15;
  FlatnessTest flatness = FlatnessTest::kAllNeighbours;
  int passes = 1;
};

struct ThinningReport {
  size_t points_in = 0;
  size_t duplicates = 0;           // points at the x, y of an earlier point, left out
  size_t dropped = 0;              // thinned out, duplicates not counted
  size_t kept = 0;                 // points_in - duplicates - dropped
  double cell_area_threshold = 0;  // 0 when density was judged by a window
  size_t dense = 0;                // points judged dense in the first pass
  int passes_run = 0;              // passes that dropped something
};

struct ThinningResult {
  std::vector<uint32_t> kept;     // indices into the input, ascending
  std::vector<uint32_t> dropped;  // indices into the input, ascending (duplicates not included)
  ThinningReport report;
};

// Thins `points` as described above. Returns InvalidArgument "point I: x, y or z is not finite"
// for the first non-finite point, and for options out of range (thresholds negative or not
// finite, median_fraction or max_cell_area not positive, a window's area not positive or
// max_points negative, passes < 1).
Result<ThinningResult> ThinByVoronoiDensity(const std::vector<TinVertex>& points,
                                            const ThinningOptions& options);

}  // namespace tinbase
