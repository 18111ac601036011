// Tolerance refinement: greedy insertion of DEM samples into a constrained Delaunay
// triangulation until the TIN is within a vertical tolerance of the DEM (Garland and Heckbert
// 1995; docs/design.md, "Where the ideas come from"), over the whole triangulation or a region of
// it.
//
// Every face of the region keeps its worst-approximated valid DEM sample (core/tin/tin_raster.h
// defines which cells a face covers and its z there) in a priority queue; the worst sample of
// all is inserted as a vertex (kind kDem, z the cell's value) and only the faces that insertion
// created are rescanned. Constraints already in the Cdt are respected: a face's conflict zone
// never crosses a constrained edge, so a region bounded by constrained edges stays the region.
// The greedy builder is this refinement started from the grid's corners; the update engine runs
// it inside a conflict region whose outline it has constrained.
// Thread-safety: works on the caller's Cdt; with RefineOptions::parallel_scans its scans run on
// TBB's threads, changing nothing in the result.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/geometry/cdt.h"
#include "core/raster/cell_source.h"
#include "core/raster/grid.h"

namespace tinbase {

struct RefineOptions {
  double tolerance = 1.0;  // metres; > 0
  int64_t max_points = 0;  // at most this many new vertices; 0: no limit
  // Cells whose centre (world x, y) it returns true for are not approximated (replace
  // polygons: their inside is flat by design). Null: every valid cell counts.
  std::function<bool(double x, double y)> excluded;
  // The faces to refine, by their vertex indices: only faces it accepts are scanned, initial ones
  // and those insertions create (a point inserted on a boundary edge of the region also creates
  // faces beyond it). Null: every face.
  std::function<bool(const std::array<uint32_t, 3>& face)> in_region;
  // 0: always insert the worst sample of all (Garland-Heckbert's order). > 0: insert in passes
  // over tiles of tile x tile cells, each pass taking what is worse than a level that falls to
  // the tolerance, so a DEM streamed from a store is read nearly in order; the same error bound,
  // a slightly different (usually a little larger) point set.
  int64_t tile = 0;
  // Share scans between threads (TBB, as many as the arena has): a face over very many cells
  // (the first ones span the grid) by ranges of its rows, and the faces one insertion makes,
  // when they hold a few thousand cells together, by faces. The same result on any number of
  // threads, faster on coarse tolerances, where those scans are most of the work. Only where the
  // DEM may be read from several threads at once (CellSource::ConcurrentReads); otherwise
  // ignored. `excluded` is then called from several threads.
  bool parallel_scans = false;
};

struct RefineReport {
  int64_t points_added = 0;
  bool reached = true;  // false when max_points stopped it first
};

// Inserts DEM cell centres into `cdt` until every valid, non-excluded cell covered by a face of
// the region (options.in_region, or every finite face) is within options.tolerance of the face's
// plane. Returns the indices of the new vertices in
// insertion order. The DEM may be streamed (core/raster/cell_source.h): cells it fails to read
// count as nodata, and the caller checks dem.status() afterwards. REQUIRES: every vertex of `cdt`
// has an index (Cdt::IndexCrossings after constraints crossed), options.tolerance > 0.
std::vector<uint32_t> RefineToTolerance(Cdt& cdt, CellSource& dem, const RefineOptions& options,
                                        RefineReport* report = nullptr);
// The same, scanning at first only `faces` (and then those insertions create): for a
// triangulation whose other faces are known to be within the tolerance, as after joining two
// refined halves (Cdt::Absorb).
std::vector<uint32_t> RefineFacesToTolerance(Cdt& cdt, CellSource& dem,
                                             const RefineOptions& options,
                                             std::vector<Cdt::FaceRef> faces,
                                             RefineReport* report = nullptr);
// The same over a grid in memory. REQUIRES: dem's cells match its geometry.
std::vector<uint32_t> RefineToTolerance(Cdt& cdt, const Grid& dem, const RefineOptions& options,
                                        RefineReport* report = nullptr);

}  // namespace tinbase
