// Test contours made from a real DEM with GDAL's own contour generator (GDALContourGenerate),
// independent of the code under test. Header-only; thread-safety as GDAL's.
#pragma once

#include <gdal.h>
#include <gdal_alg.h>
#include <ogr_api.h>

#include <string>

#include "core/base/status.h"

namespace tinbase::testing {

// Writes the contours of band 1 of `raster` every `interval` (from 0) to `out` (GeoPackage or
// GeoJSON by extension; layer "contour", fields ID and ELEV, the raster's CRS), honouring the
// band's nodata. IOError naming the file on failure.
inline Status MakeContours(const std::string& raster, const std::string& out, double interval) {
  GDALAllRegister();
  GDALDatasetH src = GDALOpen(raster.c_str(), GA_ReadOnly);
  if (src == nullptr) return Status::IOError(raster + ": GDAL cannot open it");
  const bool json = out.size() > 8 && out.substr(out.size() - 8) == ".geojson";
  GDALDriverH driver = GDALGetDriverByName(json ? "GeoJSON" : "GPKG");
  GDALDatasetH dst = GDALCreate(driver, out.c_str(), 0, 0, 0, GDT_Unknown, nullptr);
  if (dst == nullptr) {
    GDALClose(src);
    return Status::IOError(out + ": GDAL cannot create it");
  }
  OGRLayerH layer =
      GDALDatasetCreateLayer(dst, "contour", GDALGetSpatialRef(src), wkbLineString, nullptr);
  OGRFieldDefnH id = OGR_Fld_Create("ID", OFTInteger);
  OGRFieldDefnH elev = OGR_Fld_Create("ELEV", OFTReal);
  OGR_L_CreateField(layer, id, 0);
  OGR_L_CreateField(layer, elev, 0);
  OGR_Fld_Destroy(id);
  OGR_Fld_Destroy(elev);
  GDALRasterBandH band = GDALGetRasterBand(src, 1);
  int has_nodata = 0;
  const double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
  const CPLErr err = GDALContourGenerate(band, interval, 0.0, 0, nullptr, has_nodata, nodata, layer,
                                         0, 1, nullptr, nullptr);
  GDALClose(dst);
  GDALClose(src);
  if (err != CE_None) return Status::IOError(out + ": contour generation failed");
  return Status::Ok();
}

}  // namespace tinbase::testing
