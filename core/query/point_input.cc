#include "core/query/point_input.h"

#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "core/base/number_text.h"
#include "core/geometry/point_list.h"
#include "core/vector/gdal_session.h"

namespace tinbase {

namespace {

// The whole field as a usable number (core/base/number_text.h); nullopt otherwise.
std::optional<double> Number(std::string_view field) {
  const NumberText n = ParseNumberText(field);
  if (n.problem) return std::nullopt;
  return n.value;
}

// The points of x,y text (core/geometry/point_list.h); InvalidArgument when there are none.
Result<std::vector<Point2>> ReadText(std::istream& in, const std::string& name) {
  TB_ASSIGN_OR_RETURN(std::vector<Point2> points, ReadPointList(in, name));
  if (points.empty()) return Status::InvalidArgument(name + ": no points");
  return points;
}

struct TransformDeleter {
  void operator()(OGRCoordinateTransformation* t) const {
    OGRCoordinateTransformation::DestroyCT(t);
  }
};
using TransformPtr = std::unique_ptr<OGRCoordinateTransformation, TransformDeleter>;

// The transformation from the layer's CRS to `target`; null when none is needed (no target, no
// layer CRS, or the same system).
Result<TransformPtr> TransformTo(OGRLayer& layer, const std::optional<Crs>& target,
                                 const std::string& name) {
  const OGRSpatialReference* srs = layer.GetSpatialRef();
  if (!target || srs == nullptr) return TransformPtr();
  char* wkt = nullptr;
  srs->exportToWkt(&wkt);
  Result<Crs> source = Crs::FromWkt(wkt != nullptr ? wkt : "");
  CPLFree(wkt);
  if (!source.ok()) return source.status().WithContext(name);
  if (source->IsSame(*target)) return TransformPtr();
  TransformPtr t(OGRCreateCoordinateTransformation(&source->ogr(), &target->ogr()));
  if (!t)
    return Status::InvalidArgument(name + ": no transformation from " + source->Label() + " to " +
                                   target->Label() + LastGdalError());
  return t;
}

Result<std::vector<Point2>> ReadOgrPoints(GDALDataset& ds, const std::optional<Crs>& target,
                                          const std::string& name) {
  if (ds.GetLayerCount() != 1)
    return Status::InvalidArgument(name + ": " + std::to_string(ds.GetLayerCount()) +
                                   " layers, expected one point layer");
  OGRLayer& layer = *ds.GetLayer(0);
  TB_ASSIGN_OR_RETURN(TransformPtr transform, TransformTo(layer, target, name));
  std::vector<Point2> points;
  int64_t index = 0;
  for (auto& feature : layer) {
    const int64_t fid = feature->GetFID() != OGRNullFID ? feature->GetFID() : index;
    ++index;
    const std::string where = name + " feature " + std::to_string(fid);
    const OGRGeometry* g = feature->GetGeometryRef();
    if (g == nullptr || g->IsEmpty())
      return Status::InvalidArgument(where + ": feature has no geometry");
    if (wkbFlatten(g->getGeometryType()) != wkbPoint)
      return Status::InvalidArgument(where + ": geometry is a " +
                                     std::string(g->getGeometryName()) + ", not a point");
    const auto* p = g->toPoint();
    double x = p->getX(), y = p->getY();
    if (transform && !transform->Transform(1, &x, &y))
      return Status::InvalidArgument(where + ": cannot be reprojected" + LastGdalError());
    if (CheckNumber(x) || CheckNumber(y))
      return Status::InvalidArgument(where + ": coordinates are not finite or beyond 1e15");
    points.push_back({x, y});
  }
  if (points.empty()) return Status::InvalidArgument(name + ": no points");
  return points;
}

// The vertices of the only feature of a LineString layer; nullopt when the layer's first feature
// is not a line (then it is read as points).
Result<std::optional<std::vector<Point2>>> ReadOgrLine(GDALDataset& ds,
                                                       const std::optional<Crs>& target,
                                                       const std::string& name) {
  if (ds.GetLayerCount() != 1) return std::optional<std::vector<Point2>>();
  OGRLayer& layer = *ds.GetLayer(0);
  layer.ResetReading();
  std::unique_ptr<OGRFeature> first(layer.GetNextFeature());
  if (!first || first->GetGeometryRef() == nullptr ||
      wkbFlatten(first->GetGeometryRef()->getGeometryType()) != wkbLineString)
    return std::optional<std::vector<Point2>>();
  if (layer.GetFeatureCount() != 1)
    return Status::InvalidArgument(name + ": " + std::to_string(layer.GetFeatureCount()) +
                                   " line features, expected one");
  TB_ASSIGN_OR_RETURN(TransformPtr transform, TransformTo(layer, target, name));
  const auto* line = first->GetGeometryRef()->toLineString();
  std::vector<Point2> points;
  for (int i = 0; i < line->getNumPoints(); ++i) {
    double x = line->getX(i), y = line->getY(i);
    const std::string where = name + ", vertex " + std::to_string(i);
    if (transform && !transform->Transform(1, &x, &y))
      return Status::InvalidArgument(where + ": cannot be reprojected" + LastGdalError());
    if (CheckNumber(x) || CheckNumber(y))
      return Status::InvalidArgument(where + ": coordinates are not finite or beyond 1e15");
    points.push_back({x, y});
  }
  return std::optional<std::vector<Point2>>(std::move(points));
}

// A vector source OGR opens at `path`, or null for anything else (then read as text). GDAL's CSV
// driver would take x,y text too, without naming a bad line, so text stays ours.
GdalDatasetPtr OpenVector(const std::string& path) {
  RegisterGdalDriversOnce();
  QuietGdalErrors quiet;
  GdalDatasetPtr ds(static_cast<GDALDataset*>(
      GDALOpenEx(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr)));
  if (ds && std::string(ds->GetDriver()->GetDescription()) == "CSV") ds.reset();
  return ds;
}

enum class Shape { kPoints, kLine };

Result<std::vector<Point2>> Read(const std::string& path, const std::optional<Crs>& target,
                                 Shape shape) {
  if (path == "-") return ReadText(std::cin, "standard input");
  const std::string name = std::filesystem::path(path).filename().string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return Status::NotFound(path + ": no such file");
  if (GdalDatasetPtr ds = OpenVector(path)) {
    if (shape == Shape::kLine) {
      TB_ASSIGN_OR_RETURN(auto line, ReadOgrLine(*ds, target, name));
      if (line) return std::move(*line);
    }
    return ReadOgrPoints(*ds, target, name);
  }
  std::ifstream in(path);
  if (!in) return Status::IOError(path + ": cannot be read");
  return ReadText(in, name);
}

}  // namespace

Result<std::vector<Point2>> ReadPoints(const std::string& path, const std::optional<Crs>& target) {
  return Read(path, target, Shape::kPoints);
}

Result<std::vector<Point2>> ReadLine(const std::string& path, const std::optional<Crs>& target) {
  return Read(path, target, Shape::kLine);
}

Result<std::vector<Point2>> ParsePointList(const std::string& text, const std::string& what) {
  std::vector<Point2> points;
  std::string token;
  const auto take = [&]() -> Status {
    if (token.empty()) return Status::Ok();
    const std::string where = what + " '" + text + "': point " + std::to_string(points.size() + 1);
    const size_t comma = token.find(',');
    std::optional<double> x, y;
    if (comma != std::string::npos) {
      x = Number(std::string_view(token).substr(0, comma));
      y = Number(std::string_view(token).substr(comma + 1));
    }
    if (!x || !y) return Status::InvalidArgument(where + " '" + token + "' is not x,y");
    points.push_back({*x, *y});
    token.clear();
    return Status::Ok();
  };
  for (char c : text) {
    if (std::isspace(static_cast<unsigned char>(c)) || c == ';') {
      TB_RETURN_IF_ERROR(take());
    } else {
      token += c;
    }
  }
  TB_RETURN_IF_ERROR(take());
  if (points.empty()) return Status::InvalidArgument(what + " '" + text + "': no points");
  return points;
}

}  // namespace tinbase
