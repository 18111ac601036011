// DataAreaClip: polygons cut to the part of the plan where a surface has data (docs/design.md,
// "Polygons that overhang the surface").
//
// A surface draped on a DEM has data inside its hull (the rectangle of the cell centres it was
// built on, where every builder puts its corners) wherever the DEM gives an elevation: bilinear
// sampling (core/raster/bilinear.h) leaves nodata cells out and has none only where all four cells
// around a point are nodata, so the area without data is a union of squares between cell centres. A
// polygon digitised on a map larger than the DEM overhangs that area; clipping keeps the part on it
// and measures what was cut. The set operations are GEOS's, through OGR (GDAL is built with GEOS on
// Debian); their output rings pass MakeValidPolygon like any polygon read from a file.
// Thread-safety: pure functions.
#pragma once

#include <vector>

#include "core/base/status.h"
#include "core/geometry/polygon.h"
#include "core/raster/grid.h"

namespace tinbase {

// An axis-aligned rectangle in plan view (closed).
struct PlanRect {
  double min_x = 0;
  double min_y = 0;
  double max_x = 0;
  double max_y = 0;
};

// Where a surface has data: its hull minus the squares without elevation.
struct DataArea {
  PlanRect hull;
  std::vector<PlanRect> nodata;  // NoElevationRectangles
  // The part of a clipped polygon narrower than this (map units squared) is dropped with the cut:
  // a sliver between a ring and a nodata cell's edge would only make needle triangles.
  double min_piece_area = 0;
  // How far clipped rings stay off the hull's and the nodata squares' edges (map units, >= 0):
  // GEOS computes the crossing of a ring with an edge in floating point, a vertex an ulp outside
  // the hull would lie outside the surface, and on a nodata square's edge bilinear sampling gives
  // the valid cells beyond it no weight.
  double hull_inset = 0;
};

enum class ClipVerdict {
  kInside,   // every polygon lies in the data area: returned unchanged
  kCut,      // a part lay outside: `polygons` is what is inside
  kOutside,  // nothing of the polygons lies in the data area
};

struct DataAreaClip {
  ClipVerdict verdict = ClipVerdict::kInside;
  std::vector<Polygon> polygons;  // valid (MakeValidPolygon), shells counter-clockwise
  double area_outside = 0;        // plan area cut away, map units squared
};

// The polygons (one feature's, non-overlapping) clipped to `area`. InvalidArgument when GDAL
// lacks GEOS, or when GEOS returns a piece that is not a valid polygon (message naming it).
Result<DataAreaClip> ClipToDataArea(const std::vector<Polygon>& polygons, const DataArea& area);

// The squares between cell centres of `grid` whose four cells are all nodata (where bilinear
// sampling gives no elevation), as few rectangles: runs along each row, a run repeated on the rows
// below merged into one rectangle. Corners are the grid's cell centres.
std::vector<PlanRect> NoElevationRectangles(const Grid& grid);

}  // namespace tinbase
