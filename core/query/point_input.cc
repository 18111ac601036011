#include "core/query/point_input.h"

#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "core/vector/gdal_session.h"

namespace tinbase {

namespace {

std::string_view Trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// The fields of a line: split at commas when it has one (CSV), else at runs of whitespace.
std::vector<std::string_view> Fields(std::string_view line) {
  std::vector<std::string_view> fields;
  if (line.find(',') != std::string_view::npos) {
    size_t start = 0;
    for (;;) {
      const size_t comma = line.find(',', start);
      fields.push_back(Trim(line.substr(start, comma - start)));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    return fields;
  }
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
  return fields;
}

// The whole field as a double; nullopt when it is not exactly one number.
std::optional<double> Number(std::string_view field) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (ec != std::errc() || end != field.data() + field.size() || field.empty()) return std::nullopt;
  return value;
}

std::string Lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

// The column of the header named one of `names`, or -1.
int ColumnNamed(const std::vector<std::string_view>& header,
                std::initializer_list<const char*> names) {
  for (size_t i = 0; i < header.size(); ++i) {
    std::string field = Lower(header[i]);
    if (field.size() >= 2 && field.front() == '"' && field.back() == '"')
      field = field.substr(1, field.size() - 2);
    for (const char* name : names)
      if (field == name) return static_cast<int>(i);
  }
  return -1;
}

struct Columns {
  int x = 0;
  int y = 1;
};

Result<Columns> HeaderColumns(const std::vector<std::string_view>& header,
                              const std::string& where) {
  Columns c{ColumnNamed(header, {"x", "easting"}), ColumnNamed(header, {"y", "northing"})};
  if (c.x < 0 || c.y < 0)
    return Status::InvalidArgument(where +
                                   ": the header names no x and y columns (x,y or "
                                   "easting,northing)");
  return c;
}

// The field as a finite coordinate; InvalidArgument naming the axis and the place otherwise.
Result<double> Coordinate(std::string_view field, const char* axis, const std::string& where) {
  const std::optional<double> value = Number(field);
  if (!value)
    return Status::InvalidArgument(where + ": " + axis + " '" + std::string(field) +
                                   "' is not a number");
  if (!std::isfinite(*value))
    return Status::InvalidArgument(where + ": " + axis + " '" + std::string(field) +
                                   "' is not finite");
  return *value;
}

std::string LineWhere(const std::string& name, int64_t line) {
  return name + ", line " + std::to_string(line);
}

}  // namespace

Result<std::vector<Point2>> ReadPointText(std::istream& in, const std::string& name) {
  std::vector<Point2> points;
  std::optional<Columns> columns;
  std::string text;
  int64_t line = 0;
  while (std::getline(in, text)) {
    ++line;
    const std::string_view trimmed = Trim(text);
    if (trimmed.empty() || trimmed.front() == '#') continue;
    const std::vector<std::string_view> fields = Fields(trimmed);
    const std::string where = LineWhere(name, line);
    if (!columns) {
      if (!Number(fields.front())) {
        TB_ASSIGN_OR_RETURN(columns, HeaderColumns(fields, where));
        continue;
      }
      columns = Columns{};
    }
    const int needed = std::max(columns->x, columns->y) + 1;
    if (static_cast<int>(fields.size()) < needed)
      return Status::InvalidArgument(where + ": " + std::to_string(fields.size()) +
                                     " field(s), expected at least " + std::to_string(needed) +
                                     " (x, y)");
    TB_ASSIGN_OR_RETURN(const double x, Coordinate(fields[columns->x], "x", where));
    TB_ASSIGN_OR_RETURN(const double y, Coordinate(fields[columns->y], "y", where));
    points.push_back({x, y});
  }
  if (in.bad()) return Status::IOError(name + ": read failed at line " + std::to_string(line + 1));
  if (points.empty()) return Status::InvalidArgument(name + ": no points");
  return points;
}

namespace {

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
    if (!std::isfinite(x) || !std::isfinite(y))
      return Status::InvalidArgument(where + ": coordinates are not finite");
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
    if (!std::isfinite(x) || !std::isfinite(y))
      return Status::InvalidArgument(where + ": coordinates are not finite");
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
  if (path == "-") return ReadPointText(std::cin, "standard input");
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
  return ReadPointText(in, name);
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
    if (!x || !y || !std::isfinite(*x) || !std::isfinite(*y))
      return Status::InvalidArgument(where + " '" + token + "' is not x,y");
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
