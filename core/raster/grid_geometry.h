// GridGeometry: where the cells of a north-up raster lie in the world.
//
// Cell (col, row) covers [origin_x + col*cell_x, origin_x + (col+1)*cell_x] in x and likewise in y
// with cell_y < 0 for north-up rasters (GDAL's geotransform without rotation terms). A cell's value
// stands for its centre, as in GDAL's bilinear resampling. Plain value type.
#pragma once

#include <cmath>
#include <cstdint>

namespace tinbase {

struct GridGeometry {
  double origin_x = 0;  // x of the left edge of column 0
  double origin_y = 0;  // y of the top edge of row 0
  double cell_x = 1;    // > 0
  double cell_y = -1;   // < 0 for north-up
  int64_t width = 0;
  int64_t height = 0;

  double CellCenterX(int64_t col) const {
    return origin_x + (static_cast<double>(col) + 0.5) * cell_x;
  }
  double CellCenterY(int64_t row) const {
    return origin_y + (static_cast<double>(row) + 0.5) * cell_y;
  }
  // Fractional column/row in "centre space": 0.0 is the centre of column 0.
  double ColumnAt(double x) const { return (x - origin_x) / cell_x - 0.5; }
  double RowAt(double y) const { return (y - origin_y) / cell_y - 0.5; }

  double MinX() const { return origin_x; }
  double MaxX() const { return origin_x + static_cast<double>(width) * cell_x; }
  double MinY() const {
    return cell_y < 0 ? origin_y + static_cast<double>(height) * cell_y : origin_y;
  }
  double MaxY() const {
    return cell_y < 0 ? origin_y : origin_y + static_cast<double>(height) * cell_y;
  }
  bool Contains(double x, double y) const {
    return x >= MinX() && x <= MaxX() && y >= MinY() && y <= MaxY();
  }
  int64_t CellCount() const { return width * height; }
};

}  // namespace tinbase
