// Split refinement: greedy insertion to a tolerance in two halves refined side by side (TBB
// tasks), for a grid in memory.
//
// The grid is cut in two along a column (or row, across its longer side): the seam, near the
// line that gives both halves as much work. The seam's own cells are approximated first, alone,
// by a polyline of cell centres (1D greedy insertion), so both halves start from the same
// boundary chain. Each half is then refined as a task of its own from its four corners and that
// chain, never inserting a seam cell, so its boundary chain stays the same. The halves are
// joined (Cdt::Absorb flips the edges near the seam back to Delaunay), and the faces the join
// made or that touch the seam are refined again, like any other face.
//
// Why the result keeps the bound: a face that the join did not change and that has no vertex on
// the seam is a face of one half, the same vertices in the same order, so it covers the same
// cells with the same plane as when that half's refinement last scanned it and found it within
// the tolerance; every other face is scanned again.
//
// What a split costs: the chain's vertices. An unsplit TIN crosses the seam line with edges
// and rarely has a vertex on it, so nearly every chain vertex is one more than it would hold.
// The seam is therefore the line with the shortest chain near the balance line, and a caller
// that may choose (GreedySplit::kAutomatic) does not split when even that chain is short:
// the TIN is then small (a TIN of n vertices has a chain of about sqrt(n / 2) on generated and
// SRTM terrains, so a chain of k costs about 1 / (2k) more vertices) and builds quickly.
//
// Whether a grid is split depends on the grid and the tolerance alone, never on the number of
// threads: with one thread the halves are refined one after the other, to the same TIN.
// Thread-safety: reads `dem` from two threads at once; it must not change meanwhile.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>

#include "core/geometry/cdt.h"
#include "core/raster/grid.h"

namespace tinbase {

// The z of a hull vertex at cell (col, row): the cell's value, or a substitute on nodata.
using BoundaryElevationFn = std::function<double(int64_t col, int64_t row)>;

// A chain shorter than this keeps an automatic build unsplit. Measured: chains of 14 and
// 20 (generated 1025^2 and 2049^2 at 20 m) cost 3.5 % and 1.9 % more triangles than no split,
// past or near the 2 % over delatin that issue 4 allows; on those grids chains of 48 and longer
// cost under 1 % (but see kMaxSeamCellsPerVertex for larger grids).
inline constexpr size_t kMinSeamVertices = 32;
// Nor may the chain be sparser than one vertex per this many cells of the seam: a sparse chain
// means a surface coarse for its grid, where the halves, refined apart, differ most from one
// greedy run. Measured (2026-11-24): generated 4097^2 at 20 m, a chain of 50 on 4097 cells, cost
// 2.2 % more triangles than no split; chains of one vertex per 22 cells or denser (generated
// 1025^2 at 5 m: 47) cost under 1 %.
inline constexpr int64_t kMaxSeamCellsPerVertex = 40;

// The chain length below which an automatic build of `g` is not split: kMinSeamVertices,
// or one vertex per kMaxSeamCellsPerVertex cells of the seam (the grid's shorter side, which the
// seam runs along), whichever is more.
size_t MinSeamVertices(const GridGeometry& g);

// True when `dem` is large enough for a split to pay: at least 3 cells across its longer side,
// so the seam has a half on each side, and enough cells that the work dwarfs handing a half to
// another thread and choosing the seam.
bool WorthSplitting(const GridGeometry& g);

// Where a grid is cut: column `at` (vertical) or row `at`, and how many vertices its chain has
// at a given tolerance.
struct SeamChoice {
  bool vertical = true;
  int64_t at = 0;
  size_t chain_vertices = 0;
};

// Returns the seam: across the longer side (columns when the grid is square), the line within
// 1/20 of that side from the line that splits the work evenly (estimated from the chains of 32
// lines spread across the grid: a terrain rough on one side and smooth on the other is not cut
// in its middle) whose chain has the fewest vertices at `tolerance`; among equals, the one
// nearest the balance line. Lines are tried at steps of 1/200 of the side. REQUIRES: the grid
// is at least 3 cells across its longer side, dem's cells match its geometry, tolerance > 0,
// boundary_z returns a finite z for every cell on the grid's hull.
SeamChoice ChooseSeam(const Grid& dem, double tolerance, const BoundaryElevationFn& boundary_z);

// Returns a Delaunay triangulation of cell centres of `dem` (four grid corners included, their
// z from `boundary_z` like that of the seam's two ends) in which every valid cell is within
// `tolerance` of the face covering it, refined in halves side by side along ChooseSeam's seam;
// or nullopt, without refining, when that seam's chain has fewer than `min_seam_vertices`
// vertices (0: never). REQUIRES: as ChooseSeam.
std::optional<Cdt> RefineInHalves(const Grid& dem, double tolerance,
                                  const BoundaryElevationFn& boundary_z,
                                  size_t min_seam_vertices = 0);

}  // namespace tinbase
