#include "core/raster/gdal_raster.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal_alg.h>
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <string_view>

#include "core/vector/gdal_session.h"

namespace tinbase {

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// GDAL reports through a global error handler; here its message goes into our Status instead of
// stderr, and the caller's handler is restored on the way out.
class QuietGdal {
 public:
  QuietGdal() : pusher_(CPLQuietErrorHandler) { CPLErrorReset(); }
  // " (GDAL: <last message>)" or "" when GDAL said nothing.
  static std::string Detail() {
    const char* msg = CPLGetLastErrorMsg();
    return msg != nullptr && *msg != '\0' ? " (GDAL: " + OneLineGdalMessage(msg) + ")" : "";
  }

 private:
  CPLErrorHandlerPusher pusher_;
};

void CloseDataset(GDALDataset* ds) {
  if (ds != nullptr) GDALClose(GDALDataset::ToHandle(ds));
}

std::string Num(double v) { return CPLSPrintf("%.17g", v); }

// An uncompressed GeoTIFF holds every cell of band 1 in the file, so a header that claims more
// cells than the file has bytes for is damaged; caught here before anything sizes a buffer or a
// loop by it. Compressed and virtual rasters cannot be bounded by their size: the importer's
// cell limit bounds them.
Status CheckSizeAgainstFile(GDALDataset& ds, const std::string& path, int64_t file_bytes) {
  if (ds.GetDriver() == nullptr || std::string_view(ds.GetDriver()->GetDescription()) != "GTiff" ||
      ds.GetRasterCount() < 1 || ds.GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE") != nullptr)
    return Status::Ok();
  const int64_t cell_bytes = GDALGetDataTypeSizeBytes(ds.GetRasterBand(1)->GetRasterDataType());
  const int64_t width = ds.GetRasterXSize(), height = ds.GetRasterYSize();
  // width, height < 2^31: their product fits int64, times cell_bytes it may not.
  if (width * height <= file_bytes / std::max<int64_t>(cell_bytes, 1)) return Status::Ok();
  return Status::Corruption(path + ": the header claims " + std::to_string(width) + " x " +
                            std::to_string(height) + " uncompressed cells of " +
                            std::to_string(cell_bytes) + " bytes, but the file has " +
                            std::to_string(file_bytes) + " bytes: truncated or damaged");
}

}  // namespace

void EnsureGdalRegistered() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

Result<GdalRaster> GdalRaster::Open(const std::string& path) {
  EnsureGdalRegistered();
  QuietGdal quiet;
  VSIStatBufL stat;
  if (VSIStatL(path.c_str(), &stat) != 0) return Status::NotFound(path + ": no such file");
  if (VSI_ISDIR(stat.st_mode))
    return Status::InvalidArgument(path + ": is a directory, not a raster");
  GDALDataset* raw = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  if (raw == nullptr)
    return Status::InvalidArgument(path + ": not a raster GDAL can read" + QuietGdal::Detail());
  // A file cut short still opens when its first directory is whole; what was lost (the CRS, the
  // geotransform, nodata) GDAL reports only as warnings of a failed read, which would otherwise
  // surface later as a misleading "no CRS".
  if (CPLGetLastErrorType() >= CE_Warning &&
      std::string_view(CPLGetLastErrorMsg()).find("IO error") != std::string_view::npos) {
    GDALClose(GDALDataset::ToHandle(raw));
    return Status::Corruption(path + ": the file is truncated or damaged" + QuietGdal::Detail());
  }
  std::shared_ptr<GDALDataset> dataset(raw, CloseDataset);
  TB_RETURN_IF_ERROR(CheckSizeAgainstFile(*dataset, path, static_cast<int64_t>(stat.st_size)));
  return FromDataset(std::move(dataset), path);
}

Result<GdalRaster> GdalRaster::FromDataset(std::shared_ptr<GDALDataset> dataset,
                                           const std::string& path) {
  if (dataset->GetRasterCount() < 1) return Status::InvalidArgument(path + ": raster has no band");
  const OGRSpatialReference* srs = dataset->GetSpatialRef();
  if (srs == nullptr || srs->IsEmpty())
    return Status::InvalidArgument(path + ": raster has no CRS");
  char* wkt = nullptr;
  const char* wkt_options[] = {"FORMAT=WKT2_2018", nullptr};
  srs->exportToWkt(&wkt, wkt_options);
  auto crs = Crs::FromWkt(wkt != nullptr ? wkt : "");
  CPLFree(wkt);
  if (!crs.ok()) return crs.status().WithContext(path);

  double gt[6];
  if (dataset->GetGeoTransform(gt) != CE_None)
    return Status::InvalidArgument(path + ": raster has no geotransform");
  if (gt[2] != 0 || gt[4] != 0)
    return Status::InvalidArgument(path + ": rotated geotransform (row/column terms " + Num(gt[2]) +
                                   ", " + Num(gt[4]) +
                                   ") is not supported; warp it north-up first");
  if (!(gt[1] > 0) || !(gt[5] < 0))
    return Status::InvalidArgument(path + ": geotransform is not north-up (cell " + Num(gt[1]) +
                                   " x " + Num(gt[5]) + "); warp it north-up first");

  GdalRaster raster;
  raster.path_ = path;
  raster.geometry_ = GridGeometry{
      gt[0], gt[3], gt[1], gt[5], dataset->GetRasterXSize(), dataset->GetRasterYSize()};
  raster.crs_ = std::move(crs).value();
  int has_nodata = 0;
  const double nodata = dataset->GetRasterBand(1)->GetNoDataValue(&has_nodata);
  if (has_nodata) raster.nodata_ = nodata;
  raster.dataset_ = std::move(dataset);
  return raster;
}

Result<std::vector<float>> GdalRaster::ReadWindow(int64_t col, int64_t row, int64_t width,
                                                  int64_t height) const {
  std::vector<float> cells(static_cast<size_t>(width * height), kNaN);
  const int64_t c0 = std::max<int64_t>(col, 0);
  const int64_t r0 = std::max<int64_t>(row, 0);
  const int64_t c1 = std::min<int64_t>(col + width, geometry_.width);
  const int64_t r1 = std::min<int64_t>(row + height, geometry_.height);
  if (c0 >= c1 || r0 >= r1) return cells;
  QuietGdal quiet;
  float* first = cells.data() + (r0 - row) * width + (c0 - col);
  const CPLErr err = dataset_->GetRasterBand(1)->RasterIO(
      GF_Read, static_cast<int>(c0), static_cast<int>(r0), static_cast<int>(c1 - c0),
      static_cast<int>(r1 - r0), first, static_cast<int>(c1 - c0), static_cast<int>(r1 - r0),
      GDT_Float32, sizeof(float), static_cast<GSpacing>(width * sizeof(float)), nullptr);
  if (err != CE_None) return Status::IOError(path_ + ": cannot read cells" + QuietGdal::Detail());
  if (nodata_ && !std::isnan(*nodata_)) {
    // Compare as float: that is the type the cells were converted to.
    const float nodata = static_cast<float>(*nodata_);
    for (int64_t r = r0; r < r1; ++r) {
      float* line = cells.data() + (r - row) * width;
      for (int64_t c = c0; c < c1; ++c)
        if (line[c - col] == nodata) line[c - col] = kNaN;
    }
  }
  return cells;
}

Result<Grid> GdalRaster::Read() const {
  Grid grid;
  TB_ASSIGN_OR_RETURN(grid.cells, ReadWindow(0, 0, geometry_.width, geometry_.height));
  grid.geometry = geometry_;
  grid.crs_wkt = crs_->Wkt();
  grid.source_nodata = nodata_;
  return grid;
}

Result<GdalRaster> GdalRaster::WarpTo(const Crs& target, const GridGeometry* align) const {
  QuietGdal quiet;
  const std::string wkt = target.Wkt();
  // -et 0: the exact transformer, so a cell's value does not depend on how GDAL chunks the
  // warp (a whole-raster read and a one-cell read of the virtual raster agree).
  CPLStringList args;
  for (const char* a : {"-of", "VRT", "-r", "bilinear", "-ot", "Float32", "-dstnodata", "nan",
                        "-et", "0", "-t_srs"})
    args.AddString(a);
  args.AddString(wkt.c_str());
  if (align != nullptr) {
    char** topts = CSLSetNameValue(nullptr, "DST_SRS", wkt.c_str());
    void* transformer =
        GDALCreateGenImgProjTransformer2(GDALDataset::ToHandle(dataset_.get()), nullptr, topts);
    CSLDestroy(topts);
    if (transformer == nullptr)
      return Status::InvalidArgument(path_ + ": cannot transform onto " + target.Label() +
                                     QuietGdal::Detail());
    double gt[6];
    double extent[4];
    int pixels = 0;
    int lines = 0;
    const CPLErr err =
        GDALSuggestedWarpOutput2(GDALDataset::ToHandle(dataset_.get()), GDALGenImgProjTransform,
                                 transformer, gt, &pixels, &lines, extent, 0);
    GDALDestroyGenImgProjTransformer(transformer);
    if (err != CE_None)
      return Status::InvalidArgument(path_ + ": cannot transform onto " + target.Label() +
                                     QuietGdal::Detail());
    // Snap the natural extent outward onto the grid lines of `align`.
    const double cx = align->cell_x;
    const double cy = -align->cell_y;
    const double min_x = align->origin_x + std::floor((extent[0] - align->origin_x) / cx) * cx;
    const double max_x = align->origin_x + std::ceil((extent[2] - align->origin_x) / cx) * cx;
    const double max_y = align->origin_y - std::floor((align->origin_y - extent[3]) / cy) * cy;
    const double min_y = align->origin_y - std::ceil((align->origin_y - extent[1]) / cy) * cy;
    for (const std::string& a : {std::string("-tr"), Num(cx), Num(cy), std::string("-te"),
                                 Num(min_x), Num(min_y), Num(max_x), Num(max_y)})
      args.AddString(a.c_str());
  }
  GDALWarpAppOptions* options = GDALWarpAppOptionsNew(args.List(), nullptr);
  if (options == nullptr)
    return Status::InvalidArgument(path_ + ": bad warp options" + QuietGdal::Detail());
  GDALDatasetH source = GDALDataset::ToHandle(dataset_.get());
  int usage_error = 0;
  GDALDatasetH warped = GDALWarp("", nullptr, 1, &source, options, &usage_error);
  GDALWarpAppOptionsFree(options);
  if (warped == nullptr)
    return Status::InvalidArgument(path_ + ": cannot warp onto " + target.Label() +
                                   QuietGdal::Detail());
  TB_ASSIGN_OR_RETURN(
      GdalRaster raster,
      FromDataset(std::shared_ptr<GDALDataset>(GDALDataset::FromHandle(warped), CloseDataset),
                  path_));
  raster.source_ = dataset_;
  return raster;
}

}  // namespace tinbase

namespace tinbase {

Status WriteGeoTiff(const Grid& grid, const std::string& path) {
  EnsureGdalRegistered();
  QuietGdal quiet;
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  const GridGeometry& g = grid.geometry;
  const char* options[] = {"COMPRESS=DEFLATE", "PREDICTOR=3", nullptr};
  std::unique_ptr<GDALDataset, void (*)(GDALDataset*)> ds(
      gtiff == nullptr
          ? nullptr
          : gtiff->Create(path.c_str(), static_cast<int>(g.width), static_cast<int>(g.height), 1,
                          GDT_Float32, const_cast<char**>(options)),
      CloseDataset);
  if (ds == nullptr) return Status::IOError(path + ": cannot create GeoTIFF" + QuietGdal::Detail());
  double gt[6] = {g.origin_x, g.cell_x, 0, g.origin_y, 0, g.cell_y};
  ds->SetGeoTransform(gt);
  if (!grid.crs_wkt.empty()) {
    OGRSpatialReference srs;
    if (srs.importFromWkt(grid.crs_wkt.c_str()) == OGRERR_NONE) ds->SetSpatialRef(&srs);
  }
  GDALRasterBand* band = ds->GetRasterBand(1);
  std::vector<float> cells = grid.cells;
  const double nodata = grid.source_nodata.value_or(std::numeric_limits<double>::quiet_NaN());
  if (!std::isnan(nodata))
    for (float& v : cells)
      if (std::isnan(v)) v = static_cast<float>(nodata);
  band->SetNoDataValue(nodata);
  if (band->RasterIO(GF_Write, 0, 0, static_cast<int>(g.width), static_cast<int>(g.height),
                     cells.data(), static_cast<int>(g.width), static_cast<int>(g.height),
                     GDT_Float32, 0, 0, nullptr) != CE_None)
    return Status::IOError(path + ": cannot write cells" + QuietGdal::Detail());
  // Closing flushes the cells; GDALClose reports a failed flush only through the error state.
  CPLErrorReset();
  ds.reset();
  if (CPLGetLastErrorType() >= CE_Failure)
    return Status::IOError(path + ": cannot finish GeoTIFF" + QuietGdal::Detail());
  return Status::Ok();
}

}  // namespace tinbase
