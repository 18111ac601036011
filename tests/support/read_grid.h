// Reads a raster file into a Grid with GDAL directly, for tests that must not depend on the
// code under test (db/dem_store) to load their data. Header-only; thread-safety as GDAL's.
#pragma once

#include <gdal_priv.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "core/base/status.h"
#include "core/raster/grid.h"

namespace tinbase::testing {

// Band 1 of `path` as float32, nodata as NaN. IOError when GDAL cannot read it.
inline Result<Grid> ReadGridWithGdal(const std::string& path) {
  GDALAllRegister();
  std::unique_ptr<GDALDataset> ds(static_cast<GDALDataset*>(GDALOpen(path.c_str(), GA_ReadOnly)));
  if (!ds) return Status::IOError(path + ": GDAL cannot open it");
  double gt[6];
  if (ds->GetGeoTransform(gt) != CE_None) return Status::IOError(path + ": no geotransform");
  Grid grid;
  grid.geometry =
      GridGeometry{gt[0], gt[3], gt[1], gt[5], ds->GetRasterXSize(), ds->GetRasterYSize()};
  if (const char* wkt = ds->GetProjectionRef(); wkt != nullptr) grid.crs_wkt = wkt;
  GDALRasterBand* band = ds->GetRasterBand(1);
  grid.cells.resize(static_cast<size_t>(grid.geometry.CellCount()));
  if (band->RasterIO(GF_Read, 0, 0, ds->GetRasterXSize(), ds->GetRasterYSize(), grid.cells.data(),
                     ds->GetRasterXSize(), ds->GetRasterYSize(), GDT_Float32, 0, 0) != CE_None) {
    return Status::IOError(path + ": cannot read band 1");
  }
  int has_nodata = 0;
  const double nodata = band->GetNoDataValue(&has_nodata);
  if (has_nodata) {
    grid.source_nodata = nodata;
    const float nodata_f = static_cast<float>(nodata);
    for (float& v : grid.cells) {
      if (v == nodata_f || (std::isnan(nodata) && std::isnan(v))) {
        v = std::numeric_limits<float>::quiet_NaN();
      }
    }
  }
  return grid;
}

}  // namespace tinbase::testing
