// RTIN: a terrain TIN from a grid DEM as a binary triangle tree (paper 000, section 4; Evans,
// Kirkpatrick and Townsend 2001, "Right-triangulated irregular networks"), with a TRUE vertical
// error bound.
//
// The tree: a right-isosceles triangle splits from its apex to the midpoint of its base
// (hypotenuse) into two children; a triangle and its base neighbour form a diamond and split
// together (a split forces the base neighbour's split, as in ROAM and @mapbox/martini), so the
// result has no cracks and no T-junctions. Every tree triangle gets as error the largest
// |plane - DEM| over EVERY valid cell it covers (edges included) — not, as martini does, the
// error at its base midpoint alone, which lets the true error exceed the nominal one
// (mapbox/martini#21). A diamond's error is the larger of its two triangles', raised to the
// errors of its four child diamonds, so a split child always forces its parents: the mesh taken
// top-down ("split a diamond while its error exceeds the tolerance") is conforming, and every
// output triangle is an unsplit tree triangle whose own error is at most the tolerance.
// The errors are computed level by level from the finest up: each level's triangles cover the
// grid about once, so the build is O(N log N) for N cells.
//
// Any grid size: the tree is built over the cell-centre lattice padded to (2^k + 1)^2, with the
// grid in its top-left corner. Padded points are not data. A tree triangle wholly outside the
// grid has error 0 (it is dropped from the output); one that straddles the grid's outline has
// infinite error, so it is always split, down to the unit level if need be, where every triangle
// lies wholly inside or outside. The output domain is therefore exactly the grid's rectangle of
// cell centres, and the conformity argument above is untouched (padding is chosen over tiling
// because tiles of unequal size would need crack fixing across tile edges). The price is finer
// triangles along the right and bottom edges where width - 1 or height - 1 has few factors of
// two. Memory: 8 bytes per padded lattice point (a float error and a float bound on the
// diamond's own triangles per diamond centre), 5 bytes per cell (vertex marks and numbers) and
// 16 per output vertex (edge slots for linking neighbours), besides the output.
//
// Two threads from a 257^2 lattice up: the error pass splits the lattice at its middle column
// (grids with nodata excepted), and the output is built from the two root triangles apart.
//
// Nodata: as in greedy_builder.h, nodata cells are not approximated, a vertex on a nodata cell
// takes the mean of the nearest valid cells, and triangles whose centroid lies on nodata are
// invisible.
//
// The result is not a Delaunay triangulation in general (on square cells it passes the
// empty-circle test up to ties, on rectangular cells it does not): store it as a `free` surface.
// Thread-safety: pure function (its threads are its own and joined before it returns).
#pragma once

#include <cstdint>

#include "core/base/status.h"
#include "core/raster/grid.h"
#include "core/tin/tin.h"

namespace tinbase {

struct RtinOptions {
  double tolerance = 1.0;  // metres; >= 0 and finite (0: only exactly planar areas merge)
};

struct RtinReport {
  double max_error = 0;  // largest |TIN - DEM| over valid cells after the build
  double rms_error = 0;
  int64_t points = 0;
  int64_t triangles = 0;
  int64_t lattice_size = 0;  // 2^k + 1, the padded side
};

// Largest grid side BuildRtinTin accepts: the padded lattice of 16385^2 points holds 1 GiB of
// errors. Tile larger DEMs first.
inline constexpr int64_t kRtinMaxSide = (int64_t{1} << 14) + 1;

// Returns the TIN (vertices at cell centres, kind kDem; triangles counter-clockwise; neighbours
// linked) and fills `report` when given. Every valid cell lies within `tolerance` of the TIN.
// InvalidArgument for a negative, NaN or infinite tolerance, an empty grid, one narrower than
// 2 x 2 cells, one with no valid cell, or a side above kRtinMaxSide.
Result<Tin> BuildRtinTin(const Grid& dem, const RtinOptions& options, RtinReport* report = nullptr);

}  // namespace tinbase
