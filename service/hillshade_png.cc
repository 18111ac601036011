// Hillshade PNGs of DEM levels, with GDAL.
#include "service/hillshade_png.h"

#include <gdal_priv.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "core/vector/gdal_session.h"
#include "service/memory_file.h"

namespace tinbase::service {

namespace {

Status GdalFailed(const std::string& step) {
  return Status::IOError("overview: " + step + " failed" + LastGdalError());
}

// The grid as a one-band float32 raster in memory, NaN as nodata.
Result<GdalDatasetPtr> InMemory(const Grid& grid) {
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  if (mem == nullptr) return GdalFailed("the MEM driver");
  const GridGeometry& g = grid.geometry;
  GdalDatasetPtr ds(mem->Create("", static_cast<int>(g.width), static_cast<int>(g.height), 1,
                                GDT_Float32, nullptr));
  if (ds == nullptr) return GdalFailed("creating the raster");
  double transform[6] = {g.origin_x, g.cell_x, 0, g.origin_y, 0, g.cell_y};
  ds->SetGeoTransform(transform);
  OGRSpatialReference srs;
  if (srs.importFromWkt(grid.crs_wkt.c_str()) != OGRERR_NONE)
    return Status::InvalidArgument("overview: the DEM's CRS is unreadable");
  ds->SetSpatialRef(&srs);
  GDALRasterBand* band = ds->GetRasterBand(1);
  band->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
  std::vector<float> cells = grid.cells;
  if (band->RasterIO(GF_Write, 0, 0, static_cast<int>(g.width), static_cast<int>(g.height),
                     cells.data(), static_cast<int>(g.width), static_cast<int>(g.height),
                     GDT_Float32, 0, 0, nullptr) != CE_None)
    return GdalFailed("writing the cells");
  return ds;
}

// GDAL's utilities take their options as argv lists.
class GdalArgs {
 public:
  explicit GdalArgs(std::initializer_list<const char*> args) {
    for (const char* a : args) list_ = CSLAddString(list_, a);
  }
  ~GdalArgs() { CSLDestroy(list_); }
  GdalArgs(const GdalArgs&) = delete;
  GdalArgs& operator=(const GdalArgs&) = delete;
  char** get() const { return list_; }

 private:
  char** list_ = nullptr;
};

Result<GdalDatasetPtr> Shade(GDALDataset* dem) {
  // -compute_edges: the outermost cells get a shade too, instead of a nodata frame.
  GdalArgs args({"-of", "MEM", "-compute_edges"});
  std::unique_ptr<GDALDEMProcessingOptions, void (*)(GDALDEMProcessingOptions*)> options(
      GDALDEMProcessingOptionsNew(args.get(), nullptr), GDALDEMProcessingOptionsFree);
  if (options == nullptr) return GdalFailed("hillshade options");
  int usage_error = 0;
  GdalDatasetPtr shade(GDALDataset::FromHandle(GDALDEMProcessing(
      "", GDALDataset::ToHandle(dem), "hillshade", nullptr, options.get(), &usage_error)));
  if (shade == nullptr) return GdalFailed("hillshade");
  return shade;
}

Result<GdalDatasetPtr> ToLonLat(GDALDataset* shade) {
  // The shade's nodata (0) becomes transparent; bilinear keeps the relief smooth.
  GdalArgs args({"-of", "MEM", "-t_srs", "EPSG:4326", "-r", "bilinear", "-dstalpha", "-srcnodata",
                 "0", "-ot", "Byte"});
  std::unique_ptr<GDALWarpAppOptions, void (*)(GDALWarpAppOptions*)> options(
      GDALWarpAppOptionsNew(args.get(), nullptr), GDALWarpAppOptionsFree);
  if (options == nullptr) return GdalFailed("warp options");
  GDALDatasetH source = GDALDataset::ToHandle(shade);
  int usage_error = 0;
  GdalDatasetPtr warped(
      GDALDataset::FromHandle(GDALWarp("", nullptr, 1, &source, options.get(), &usage_error)));
  if (warped == nullptr) return GdalFailed("warping to EPSG:4326");
  return warped;
}

}  // namespace

Result<HillshadeImage> HillshadePng(const Grid& grid) {
  if (grid.crs_wkt.empty()) return Status::InvalidArgument("overview: the DEM has no CRS");
  bool any = false;
  for (float v : grid.cells) any = any || !std::isnan(v);
  if (!any) return Status::InvalidArgument("overview: the level holds no valid cell");
  RegisterGdalDriversOnce();
  QuietGdalErrors quiet;
  TB_ASSIGN_OR_RETURN(GdalDatasetPtr dem, InMemory(grid));
  TB_ASSIGN_OR_RETURN(GdalDatasetPtr shade, Shade(dem.get()));
  TB_ASSIGN_OR_RETURN(GdalDatasetPtr warped, ToLonLat(shade.get()));
  GDALDriver* png = GetGDALDriverManager()->GetDriverByName("PNG");
  if (png == nullptr) return GdalFailed("the PNG driver");
  MemoryFile file(".png");
  GdalDatasetPtr written(
      png->CreateCopy(file.path().c_str(), warped.get(), FALSE, nullptr, nullptr, nullptr));
  if (written == nullptr) return GdalFailed("writing the PNG");
  written.reset();  // closing flushes it
  HillshadeImage image;
  TB_ASSIGN_OR_RETURN(image.png, file.Read());
  double t[6];
  if (warped->GetGeoTransform(t) != CE_None) return GdalFailed("the warped geotransform");
  image.width = warped->GetRasterXSize();
  image.height = warped->GetRasterYSize();
  image.lonlat.min_x = t[0];
  image.lonlat.max_x = t[0] + t[1] * image.width;
  image.lonlat.max_y = t[3];
  image.lonlat.min_y = t[3] + t[5] * image.height;
  return image;
}

}  // namespace tinbase::service
