// TIN on a raster grid: a Tin's elevation sampled at cell centres, and its vertical error against
// a DEM.
//
// Both builders that end in a raster (the DEM from contours) and those that start from one (edge
// collapse, reporting how far the simplified surface departs from its DEM) need "what is the
// TIN's z at this cell centre": linear interpolation in the plan-view triangle that holds the
// centre (barycentric). Every triangle counts, visible or not. Thread-safety: pure functions.
#pragma once

#include <cstdint>
#include <vector>

#include "core/raster/grid.h"
#include "core/raster/grid_geometry.h"
#include "core/tin/tin.h"

namespace tinbase {

// Row-major cells of `geometry` (width * height) holding the TIN's z at each cell centre, NaN
// where no triangle covers the centre. A centre on an edge shared by two triangles takes either
// one's value (they agree up to round-off). REQUIRES: every triangle refers to existing vertices.
std::vector<float> RasteriseTin(const Tin& tin, const GridGeometry& geometry);

struct TinGridError {
  double max_error = 0;   // largest |TIN - DEM| over compared cells
  double rms_error = 0;   // root mean square of TIN - DEM over compared cells
  int64_t cells = 0;      // valid DEM cells covered by the TIN (compared)
  int64_t uncovered = 0;  // valid DEM cells no triangle covers (not compared)
};

// |TIN - grid| at every valid cell centre of `grid`.
TinGridError CompareTinToGrid(const Tin& tin, const Grid& grid);

}  // namespace tinbase
