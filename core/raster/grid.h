// Grid: an in-memory float32 elevation raster with its geometry and CRS.
//
// Nodata cells hold NaN whatever the source used (the source's value is kept in source_nodata for
// writing the raster back out). Rows run top to bottom, row-major. Owns its cells; not
// synchronised.
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "core/raster/bilinear.h"
#include "core/raster/grid_geometry.h"

namespace tinbase {

struct Grid {
  GridGeometry geometry;
  std::string crs_wkt;                  // empty when the source had none
  std::optional<double> source_nodata;  // the source's nodata value, if it declared one
  std::vector<float> cells;             // width * height, NaN = nodata

  float At(int64_t col, int64_t row) const {
    return cells[static_cast<size_t>(row * geometry.width + col)];
  }
  bool IsValid(int64_t col, int64_t row) const { return !std::isnan(At(col, row)); }

  // Bilinear elevation at world (x, y); NaN outside the grid or where all four cells are nodata.
  double SampleBilinear(double x, double y) const {
    return tinbase::SampleBilinear(geometry, x, y,
                                   [this](int64_t c, int64_t r) { return At(c, r); });
  }
};

}  // namespace tinbase
