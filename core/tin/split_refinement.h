// Split refinement: greedy insertion to a tolerance on two threads, for a grid in memory.
//
// The grid is cut in two along its middle column (or row, across its longer side): the seam.
// The seam's own cells are approximated first, alone, by a polyline of cell centres (1D greedy
// insertion), so both halves start from the same boundary chain. Each half is then refined on
// its own thread from its four corners and that chain, never inserting a seam cell, so its
// boundary chain stays the same. The halves are joined (Cdt::Absorb flips the edges near the
// seam back to Delaunay), and the faces the join made or that touch the seam are refined again,
// on one thread, like any other face.
//
// Why the result keeps the bound: a face that the join did not change and that has no vertex on
// the seam is a face of one half, the same vertices in the same order, so it covers the same
// cells with the same plane as when that half's refinement last scanned it and found it within
// the tolerance; every other face is scanned again.
//
// Thread-safety: reads `dem` from two threads; it must not change meanwhile.
#pragma once

#include <cstdint>
#include <functional>

#include "core/geometry/cdt.h"
#include "core/raster/grid.h"

namespace tinbase {

// The z of a hull vertex at cell (col, row): the cell's value, or a substitute on nodata.
using BoundaryElevationFn = std::function<double(int64_t col, int64_t row)>;

// True when `dem` is large enough for a split to pay for its thread: at least 3 cells across
// its longer side, so the seam has a half on each side, and enough cells that the work dwarfs
// starting a thread.
bool WorthSplitting(const GridGeometry& g);

// Returns a Delaunay triangulation of cell centres of `dem` (four grid corners included, their
// z from `boundary_z` like that of the seam's two ends) in which every valid cell is within
// `tolerance` of the face covering it. REQUIRES: WorthSplitting(dem.geometry), tolerance > 0,
// dem's cells match its geometry, boundary_z returns a finite z for the grid's corners and the
// seam's ends.
Cdt RefineInHalves(const Grid& dem, double tolerance, const BoundaryElevationFn& boundary_z);

}  // namespace tinbase
