// The index map of a DEM: a hillshade of one of its overview levels as a PNG in longitude and
// latitude, so a web map lays it on the globe with the bounds it comes with.
//
// All GDAL: the level's cells go into an in-memory raster in the store's CRS, GDALDEMProcessing
// shades them there (in metres, where its slopes are right; edges computed too, nodata stays
// nodata), GDALWarp takes the shade to EPSG:4326 with an alpha band (transparent where there is
// no data), and the PNG driver writes it to /vsimem/. Thread-safety: pure function (GDAL objects
// are per call).
#pragma once

#include <string>

#include "core/base/status.h"
#include "core/raster/grid.h"
#include "db/feature_store.h"

namespace tinbase::service {

struct HillshadeImage {
  std::string png;  // grey and alpha, 8 bits each
  Box lonlat;       // the image's bounds: west, south, east, north (degrees)
  int width = 0;
  int height = 0;
};

// `grid` shaded and warped to EPSG:4326. InvalidArgument when the grid has no CRS or no valid
// cell; IOError with GDAL's message when a GDAL step fails.
Result<HillshadeImage> HillshadePng(const Grid& grid);

}  // namespace tinbase::service
