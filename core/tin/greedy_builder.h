// Greedy insertion: a terrain TIN from a grid DEM, to a vertical tolerance (papers 000/001;
// Garland and Heckbert 1995, "Fast polygonal approximation of terrains and height fields").
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

struct GreedyOptions {
  double tolerance = 1.0;  // metres; > 0
  int64_t max_points = 0;  // 0: no limit
  // 0: strict worst-first order; > 0: tiled passes (RefineOptions::tile), for a streamed DEM
  // that does not fit the block cache.
  int64_t tile = 0;
  // 1: refine on one thread. 2: on two (core/tin/split_refinement.h) when the DEM is a grid in
  // memory and neither max_points nor tile is set. 0: two when that applies, the grid is large
  // enough to pay for it (WorthSplitting) and the seam's chain has at least MinSeamVertices
  // vertices (a shorter or sparser one would weigh on a small TIN), else one. The result keeps the
  // same bound either way; the point sets differ a little (the two-thread one holds its seam's
  // vertices). When a grid in memory is refined on one thread anyway (threads 0 or 2 with
  // those options set, or 0 with a short seam), a second thread still shares its largest scans
  // (RefineOptions::parallel_scans), which changes nothing in the result. Unless threads is 1,
  // the report's errors over a grid in memory are measured on two threads.
  int threads = 0;
};

struct GreedyReport {
  double max_error = 0;  // largest |TIN - DEM| over valid cells after the build
  double rms_error = 0;
  int64_t points = 0;
};

// Returns the TIN (the four corners first, then the other vertices in insertion order, half
// by half on two threads; all of kind kDem) and fills `report` when given. InvalidArgument for
// a non-positive tolerance, an empty grid or one with no valid cell, a grid narrower than 2 x 2
// cells (its corners span no triangle), a max_points other than 0 below 4 (the corners alone
// are 4), or threads other than 0, 1 or 2.
Result<Tin> BuildGreedyTin(const Grid& dem, const GreedyOptions& options,
                           GreedyReport* report = nullptr);

// The same over a streamed DEM (core/raster/cell_source.h): the grid is read a span at a time,
// so it need not fit in memory, on one thread (a source is not shared between threads).
// Returns the source's error if a block could not be read.
Result<Tin> BuildGreedyTin(CellSource& dem, const GreedyOptions& options,
                           GreedyReport* report = nullptr);

}  // namespace tinbase
