#include "core/vector/survey_points.h"

#include <ogrsf_frmts.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <memory>
#include <set>

#include "core/base/number_text.h"
#include "core/geometry/reproject.h"
#include "core/pointcloud/point_tin.h"
#include "core/vector/gdal_session.h"

namespace tinbase {
namespace {

std::string LowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

bool IsVectorSource(const std::string& ext) {
  static const std::set<std::string> kVector = {".geojson", ".json", ".gpkg", ".shp",
                                                ".fgb",     ".gml",  ".kml"};
  return kVector.count(ext) > 0;
}

// The CRS of `layer`, or none when it names none.
Result<std::optional<Crs>> LayerCrs(OGRLayer& layer, const std::string& name) {
  const OGRSpatialReference* srs = layer.GetSpatialRef();
  if (srs == nullptr) return std::optional<Crs>();
  char* wkt = nullptr;
  srs->exportToWkt(&wkt);
  auto crs = Crs::FromWkt(wkt != nullptr ? wkt : "");
  CPLFree(wkt);
  if (!crs.ok()) return crs.status().WithContext(name);
  return std::optional<Crs>(std::move(*crs));
}

// Appends the points of one feature's geometry, named after `label`.
Status AddGeometry(const OGRGeometry* g, const std::string& label, SurveyPoints* out) {
  if (g == nullptr) return Status::InvalidArgument(label + ": no geometry");
  const OGRwkbGeometryType type = wkbFlatten(g->getGeometryType());
  if (type != wkbPoint && type != wkbMultiPoint)
    return Status::InvalidArgument(label + ": a Point or MultiPoint with z is needed, not a " +
                                   OGRGeometryTypeToName(type));
  if (!g->Is3D())
    return Status::InvalidArgument(label + ": the point has no z (survey points keep their own)");
  std::vector<const OGRPoint*> points;
  if (type == wkbPoint) {
    points.push_back(g->toPoint());
  } else {
    for (const OGRPoint* p : *g->toMultiPoint()) points.push_back(p);
  }
  for (size_t k = 0; k < points.size(); ++k) {
    const std::string name = points.size() > 1 ? label + ", point " + std::to_string(k) : label;
    const OGRPoint& p = *points[k];
    if (p.IsEmpty()) return Status::InvalidArgument(name + ": an empty point");
    if (!std::isfinite(p.getX()) || !std::isfinite(p.getY()) || !std::isfinite(p.getZ()))
      return Status::InvalidArgument(name + ": a coordinate is not a finite number");
    // The 1e15 rule of every number from outside (core/base/number_text.h).
    if (CheckNumber(p.getX()) || CheckNumber(p.getY()) || CheckNumber(p.getZ()))
      return Status::InvalidArgument(name + ": a coordinate is larger in magnitude than 1e15");
    out->points.push_back({p.getX(), p.getY(), p.getZ(), VertexKind::kUser});
    out->labels.push_back(name);
  }
  return Status::Ok();
}

Result<SurveyPoints> ReadVectorPoints(const std::string& path, std::optional<Crs>* crs) {
  RegisterGdalDriversOnce();
  QuietGdalErrors quiet;
  const std::string name = std::filesystem::path(path).filename().string();
  GdalDatasetPtr ds(static_cast<GDALDataset*>(
      GDALOpenEx(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr)));
  if (!ds) return Status::IOError(name + ": cannot open as a vector source" + LastGdalError());
  if (ds->GetLayerCount() != 1)
    return Status::InvalidArgument(name + ": " + std::to_string(ds->GetLayerCount()) +
                                   " layers; survey points come in one");
  OGRLayer& layer = *ds->GetLayer(0);
  TB_ASSIGN_OR_RETURN(*crs, LayerCrs(layer, name));
  SurveyPoints out;
  out.format = ds->GetDriver() != nullptr ? ds->GetDriver()->GetDescription() : "OGR";
  layer.ResetReading();
  for (auto& feature : layer) {
    const std::string label = name + ", feature " + std::to_string(feature->GetFID());
    TB_RETURN_IF_ERROR(AddGeometry(feature->GetGeometryRef(), label, &out));
  }
  return out;
}

Result<SurveyPoints> ReadCloudPoints(const std::string& path, std::optional<Crs>* crs) {
  SurveyPoints out;
  TB_ASSIGN_OR_RETURN(PointCloud cloud, ReadPointFile(path, &out.format));
  *crs = cloud.crs;
  const std::string name = std::filesystem::path(path).filename().string();
  out.points.reserve(cloud.points.size());
  out.labels.reserve(cloud.points.size());
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const CloudPoint& p = cloud.points[i];
    out.points.push_back({p.x, p.y, p.z, VertexKind::kUser});
    out.labels.push_back(name + ", point " + std::to_string(i + 1));
  }
  return out;
}

}  // namespace

Result<SurveyPoints> ReadSurveyPoints(const std::string& path, const std::optional<Crs>& target) {
  std::optional<Crs> crs;
  Result<SurveyPoints> read = IsVectorSource(LowerExtension(path)) ? ReadVectorPoints(path, &crs)
                                                                   : ReadCloudPoints(path, &crs);
  if (!read.ok()) return read.status();
  SurveyPoints out = std::move(*read);
  if (out.points.empty()) return Status::InvalidArgument(path + ": no points");
  if (target && crs && !crs->IsSame(*target)) {
    TB_RETURN_IF_ERROR(ReprojectXy(*crs, *target, out.points).WithContext(path));
    ConvertHeightUnits(*crs, *target, out.points);
    out.reprojected_from = crs->Label();
  }
  return out;
}

}  // namespace tinbase
