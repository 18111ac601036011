// VIP: a terrain TIN from the "very important points" of a grid DEM (paper 001; Chen and
// Guevara 1987), triangulated by Delaunay (core/geometry/cdt).
//
// Significance of an interior cell P: the mean, over the four lines through its opposite
// 8-neighbour pairs (N-S, E-W, NE-SW, NW-SE), of the VERTICAL distance from P's 3D point to the
// line. P lies over the midpoint of each pair in plan, so that distance is |z_P - (z_A + z_B)/2|.
// Vertical rather than perpendicular distance because (1) it is what the threshold is compared
// with everywhere else in tinbase (a vertical tolerance in metres) and (2) the perpendicular
// distance mixes horizontal and vertical units, meaningless on geographic grids (degrees vs
// metres, e.g. SRTM); on a projected grid the perpendicular distance is the vertical one times
// the cosine of the line's slope, so it would also under-rate features on steep ground.
//
// Kept: interior cells with significance >= threshold; the four corners always (their hull is
// then the whole grid, so the domain is the full rectangle of cell centres); and border cells by
// the same rule in one dimension, with the one line along the border, so the outline keeps the
// profile's important points too (without them the border would be a straight edge between
// corners however rugged the terrain there). A line with a nodata end is skipped; a valid cell
// with no complete line left (it is a data edge along the border, or isolated) is always kept.
// With max_points > 0 only the corners and the most significant other cells are kept (ties by
// row, then column).
//
// Nodata: as in greedy_builder.h, nodata cells are not approximated and never picked except as
// corners, where the vertex takes the mean of the nearest valid cells; triangles whose centroid
// lies on nodata are invisible.
//
// VIP has no error bound: report.max_error says what the threshold gave.
// The result is a Delaunay triangulation (store it as a `delaunay` surface).
// Thread-safety: pure function.
#pragma once

#include <cstdint>

#include "core/base/status.h"
#include "core/raster/grid.h"
#include "core/tin/tin.h"

namespace tinbase {

struct VipOptions {
  double threshold = 1.0;  // metres; >= 0 and finite (0 keeps every valid cell)
  int64_t max_points = 0;  // 0: no limit, else >= 4 (the corners)
};

struct VipReport {
  double max_error = 0;  // largest |TIN - DEM| over valid cells after the build
  double rms_error = 0;
  int64_t points = 0;
  int64_t significant_cells = 0;  // cells the threshold kept, before max_points applied
};

// The significance of cell (col, row) by the rules above: +infinity for a valid cell with no
// complete line, NaN for a nodata cell; a corner gets +infinity. REQUIRES: the cell is in `dem`.
double VipSignificance(const Grid& dem, int64_t col, int64_t row);

// Returns the TIN (vertices of kind kDem in row-major order of their cells) and fills `report`
// when given. InvalidArgument for a negative, NaN or infinite threshold, a max_points other than
// 0 below 4, an empty grid, one narrower than 2 x 2 cells, or one with no valid cell.
Result<Tin> BuildVipTin(const Grid& dem, const VipOptions& options, VipReport* report = nullptr);

}  // namespace tinbase
