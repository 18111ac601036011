// Greedy insertion: a terrain TIN from a grid DEM, to a vertical tolerance (Garland and Heckbert
// 1995, "Fast polygonal approximation of terrains and height fields"; docs/design.md, "Where the
// ideas come from").
//
// Starts from the grid's corners (with tiled passes, also a coarse lattice of cells, see
// GreedyOptions::tile), keeps for every triangle its worst-approximated DEM sample
// in a priority queue, and inserts the worst sample of all until every valid sample is within the
// tolerance (or max_points is reached). Only the triangles an insertion creates are rescanned.
// The result is a Delaunay triangulation of the chosen cell centres (CGAL). Nodata cells are not
// approximated; a vertex that falls on a nodata cell takes the mean of the valid cells nearest to
// it, and triangles whose centroid lies on nodata are invisible. Thread-safety: pure function.
#pragma once

#include <cstdint>

#include "core/base/status.h"
#include "core/raster/cell_source.h"
#include "core/raster/grid.h"
#include "core/tin/tin.h"

namespace tinbase {

// Whether a grid in memory is refined in two halves (core/tin/split_refinement.h). Either way the
// TIN keeps the same bound; the point sets differ a little (a split one holds its seam's
// vertices). Only a grid in memory with neither max_points nor tile set is ever split.
enum class GreedySplit {
  // When the grid is large enough to pay for it (WorthSplitting) and the seam's chain has at
  // least MinSeamVertices vertices (a shorter or sparser one would weigh on a small TIN).
  kAutomatic,
  kNever,
  kAlways,  // whenever the grid is at least 3 cells across its longer side
};

struct GreedyOptions {
  double tolerance = 1.0;  // metres; > 0
  int64_t max_points = 0;  // 0: no limit
  // 0: strict worst-first order; > 0: tiled passes (RefineOptions::tile), for a streamed DEM
  // that does not fit the block cache.
  int64_t tile = 0;
  // Whether a grid in memory is refined in two halves side by side (GreedySplit). The
  // choice depends on the grid and these options alone, never on the number of threads: TBB runs
  // the halves, and the largest scans of an unsplit build, on as many threads as it has, to the
  // same TIN on any number.
  GreedySplit split = GreedySplit::kAutomatic;
};

struct GreedyReport {
  double max_error = 0;  // largest |TIN - DEM| over valid cells after the build
  double rms_error = 0;
  int64_t points = 0;
};

// Returns the TIN (the four corners first, then the other vertices in insertion order, half
// by half when split; all of kind kDem) and fills `report` when given; the same TIN and report
// on any number of threads. InvalidArgument for a non-positive tolerance, an empty grid or one
// with no valid cell, a grid narrower than 2 x 2 cells (its corners span no triangle), or a
// max_points other than 0 below 4 (the corners alone are 4).
Result<Tin> BuildGreedyTin(const Grid& dem, const GreedyOptions& options,
                           GreedyReport* report = nullptr);

// The same over a streamed DEM (core/raster/cell_source.h): the grid is read a span at a time,
// so it need not fit in memory, and never split; its scans are shared between threads only
// when the source allows concurrent reads (CellSource::ConcurrentReads).
// Returns the source's error if a block could not be read.
Result<Tin> BuildGreedyTin(CellSource& dem, const GreedyOptions& options,
                           GreedyReport* report = nullptr);

}  // namespace tinbase
