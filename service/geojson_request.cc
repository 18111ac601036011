// GeoJSON request bodies: JSON checked shape by shape, reprojected, then validated as the
// editor's polygons and lines.
#include "service/geojson_request.h"

#include <ogr_spatialref.h>

#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "core/geometry/polygon.h"
#include "core/vector/gdal_session.h"

namespace tinbase::service {

namespace {

using nlohmann::json;

struct TransformDeleter {
  void operator()(OGRCoordinateTransformation* t) const {
    OGRCoordinateTransformation::DestroyCT(t);
  }
};
using Transform = std::unique_ptr<OGRCoordinateTransformation, TransformDeleter>;

// Where the coordinates come from and go to; `transform` is null when they stay as they are.
struct Reprojection {
  Transform transform;
  std::string label;  // "from EPSG:4326 to EPSG:32632"
};

Result<Reprojection> MakeReprojection(const std::optional<Crs>& source, const Crs& target) {
  Reprojection r;
  if (!source || source->IsSame(target)) return r;
  r.label = "from " + source->Label() + " to " + target.Label();
  r.transform.reset(OGRCreateCoordinateTransformation(&source->ogr(), &target.ogr()));
  if (!r.transform) return Status::InvalidArgument("no transformation " + r.label);
  return r;
}

std::string TypeName(const json& j) { return j.type_name(); }

// The member `key` of object `j`, which must be of the kind `is` accepts; `what` names it.
Result<const json*> Member(const json& j, const char* key, bool (json::*is)() const noexcept,
                           const std::string& what, const char* kind) {
  const auto it = j.find(key);
  if (it == j.end()) return Status::InvalidArgument(what + ": no \"" + key + "\" member");
  if (!((*it).*is)())
    return Status::InvalidArgument(what + ": \"" + key + "\" is " + TypeName(*it) + ", not " +
                                   kind);
  return &*it;
}

// The points of a ring or line: positions of 2 or 3 finite numbers (z is dropped: features are
// draped on the DEM), reprojected.
Result<std::vector<Point2>> ReadPositions(const json& positions, const Reprojection& reprojection,
                                          const std::string& what) {
  if (!positions.is_array())
    return Status::InvalidArgument(what + ": coordinates are " + TypeName(positions) +
                                   ", not an array of positions");
  std::vector<Point2> points;
  for (size_t v = 0; v < positions.size(); ++v) {
    const json& p = positions[v];
    const std::string where = what + ", vertex " + std::to_string(v);
    if (!p.is_array() || p.size() < 2 || p.size() > 3)
      return Status::InvalidArgument(where + ": a position is an array of 2 or 3 numbers, got " +
                                     p.dump());
    for (const json& c : p) {
      if (!c.is_number() || !std::isfinite(c.get<double>()))
        return Status::InvalidArgument(where + ": coordinate " + c.dump() +
                                       " is not a finite number");
    }
    points.push_back({p[0].get<double>(), p[1].get<double>()});
  }
  if (!reprojection.transform) return points;
  std::vector<double> x(points.size()), y(points.size());
  for (size_t i = 0; i < points.size(); ++i) x[i] = points[i].x, y[i] = points[i].y;
  std::vector<int> ok(points.size(), 0);
  // The overall result is ignored: the per-point flags say which vertex failed.
  reprojection.transform->Transform(static_cast<int>(points.size()), x.data(), y.data(), nullptr,
                                    ok.data());
  for (size_t i = 0; i < points.size(); ++i) {
    if (!ok[i] || !std::isfinite(x[i]) || !std::isfinite(y[i]))
      return Status::InvalidArgument(what + ", vertex " + std::to_string(i) + ": " +
                                     FormatPoint(points[i]) + " cannot be reprojected " +
                                     reprojection.label);
    points[i] = {x[i], y[i]};
  }
  return points;
}

// One polygon's rings (shell first), valid. `prefix` is "features[2], " or with "polygon 1, ".
Result<Polygon> ReadPolygon(const json& rings, const Reprojection& reprojection,
                            const std::string& prefix) {
  if (!rings.is_array() || rings.empty())
    return Status::InvalidArgument(prefix + "a polygon is a non-empty array of rings, got " +
                                   TypeName(rings));
  std::vector<Ring> read;
  for (size_t r = 0; r < rings.size(); ++r) {
    TB_ASSIGN_OR_RETURN(
        Ring ring, ReadPositions(rings[r], reprojection, prefix + "ring " + std::to_string(r)));
    read.push_back(std::move(ring));
  }
  auto valid = MakeValidPolygon(read);
  if (!valid.ok()) return Status::InvalidArgument(prefix + valid.status().message());
  return valid;
}

// One line, consecutive repeats dropped; at least 2 distinct points.
Result<std::vector<Point2>> ReadLine(const json& positions, const Reprojection& reprojection,
                                     const std::string& what) {
  TB_ASSIGN_OR_RETURN(std::vector<Point2> points, ReadPositions(positions, reprojection, what));
  std::vector<Point2> line;
  for (const Point2& p : points)
    if (line.empty() || !SamePoint(line.back(), p)) line.push_back(p);
  if (line.size() < 2)
    return Status::InvalidArgument(what + ": a line needs at least 2 distinct points");
  return line;
}

// The geometry of `feature` into out->polygons or out->lines.
Status ReadGeometry(const json& feature, const Reprojection& reprojection, const std::string& label,
                    MemoryFeature* out) {
  const auto it = feature.find("geometry");
  if (it == feature.end() || it->is_null())
    return Status::InvalidArgument(label + ": the feature has no geometry");
  const json& g = *it;
  if (!g.is_object())
    return Status::InvalidArgument(label + ": geometry is " + TypeName(g) + ", not an object");
  TB_ASSIGN_OR_RETURN(const json* type,
                      Member(g, "type", &json::is_string, label + ", geometry", "a string"));
  const std::string kind = type->get<std::string>();
  TB_ASSIGN_OR_RETURN(const json* coordinates,
                      Member(g, "coordinates", &json::is_array, label + ", geometry", "an array"));
  const std::string prefix = label + ", ";
  if (kind == "Polygon") {
    TB_ASSIGN_OR_RETURN(Polygon p, ReadPolygon(*coordinates, reprojection, prefix));
    out->polygons.push_back(std::move(p));
  } else if (kind == "MultiPolygon") {
    for (size_t k = 0; k < coordinates->size(); ++k) {
      TB_ASSIGN_OR_RETURN(Polygon p, ReadPolygon((*coordinates)[k], reprojection,
                                                 prefix + "polygon " + std::to_string(k) + ", "));
      out->polygons.push_back(std::move(p));
    }
  } else if (kind == "LineString") {
    TB_ASSIGN_OR_RETURN(auto line, ReadLine(*coordinates, reprojection, prefix + "line 0"));
    out->lines.push_back(std::move(line));
  } else if (kind == "MultiLineString") {
    for (size_t k = 0; k < coordinates->size(); ++k) {
      TB_ASSIGN_OR_RETURN(auto line, ReadLine((*coordinates)[k], reprojection,
                                              prefix + "line " + std::to_string(k)));
      out->lines.push_back(std::move(line));
    }
  } else {
    return Status::InvalidArgument(label + ": geometry is a " + kind +
                                   "; a Polygon, MultiPolygon, LineString or MultiLineString "
                                   "is needed");
  }
  if (out->polygons.empty() && out->lines.empty())
    return Status::InvalidArgument(label + ": the geometry is empty");
  return Status::Ok();
}

// properties.mode, .tag and .level into `out`; the other properties become its attributes.
Status ReadProperties(const json& feature, const std::string& label, MemoryFeature* out) {
  const auto it = feature.find("properties");
  if (it == feature.end() || it->is_null()) return Status::Ok();
  if (!it->is_object())
    return Status::InvalidArgument(label + ": properties are " + TypeName(*it) + ", not an object");
  for (const auto& [key, value] : it->items()) {
    if (key == "mode" && !value.is_null()) {
      if (!value.is_string())
        return Status::InvalidArgument(label + ": properties.mode is " + TypeName(value) +
                                       ", not a string");
      auto mode = ParseFeatureMode(value.get<std::string>());
      if (!mode.ok()) return mode.status().WithContext(label + ": properties.mode");
      out->mode = *mode;
    } else if (key == "tag" && !value.is_null()) {
      if (!value.is_string())
        return Status::InvalidArgument(label + ": properties.tag is " + TypeName(value) +
                                       ", not a string");
      out->tag = value.get<std::string>();
    } else if (key == "level" && !value.is_null()) {
      if (!value.is_number() || !std::isfinite(value.get<double>()))
        return Status::InvalidArgument(label + ": properties.level is " + value.dump() +
                                       ", not a finite number");
      out->level = value.get<double>();
    } else if (key != "mode" && key != "tag" && key != "level") {
      out->attributes[key] = value;
    }
  }
  return Status::Ok();
}

Result<MemoryFeature> ReadFeature(const json& feature, const Reprojection& reprojection,
                                  const std::string& label) {
  if (!feature.is_object())
    return Status::InvalidArgument(label + " is " + TypeName(feature) + ", not a Feature object");
  TB_ASSIGN_OR_RETURN(const json* type,
                      Member(feature, "type", &json::is_string, label, "a string"));
  if (*type != "Feature")
    return Status::InvalidArgument(label + ": type is \"" + type->get<std::string>() +
                                   "\", not \"Feature\"");
  MemoryFeature out;
  out.label = label;
  TB_RETURN_IF_ERROR(ReadProperties(feature, label, &out));
  TB_RETURN_IF_ERROR(ReadGeometry(feature, reprojection, label, &out));
  return out;
}

// "[json.exception.parse_error.101] parse error at line 1, column 9: ..." without its bracket.
std::string ParseErrorText(const json::exception& e) {
  std::string text = e.what();
  const size_t close = text.find("] ");
  return close == std::string::npos ? text : text.substr(close + 2);
}

}  // namespace

Result<std::vector<MemoryFeature>> ParseGeoJsonFeatures(std::string_view body,
                                                        const std::optional<Crs>& source_crs,
                                                        const Crs& store_crs) {
  QuietGdalErrors quiet;  // a point PROJ cannot transform is the client's, reported as a Status
  json root;
  try {
    root = json::parse(body);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number like 1e999
    return Status::InvalidArgument("malformed JSON: " + ParseErrorText(e));
  }
  if (!root.is_object())
    return Status::InvalidArgument("the body is " + TypeName(root) +
                                   ", not a GeoJSON Feature or FeatureCollection");
  TB_ASSIGN_OR_RETURN(const json* type,
                      Member(root, "type", &json::is_string, "the body", "a string"));
  TB_ASSIGN_OR_RETURN(Reprojection reprojection, MakeReprojection(source_crs, store_crs));
  std::vector<MemoryFeature> out;
  if (*type == "Feature") {
    TB_ASSIGN_OR_RETURN(MemoryFeature f, ReadFeature(root, reprojection, "feature"));
    out.push_back(std::move(f));
    return out;
  }
  if (*type != "FeatureCollection")
    return Status::InvalidArgument("the body is a GeoJSON \"" + type->get<std::string>() +
                                   "\"; a Feature or FeatureCollection is needed");
  TB_ASSIGN_OR_RETURN(const json* features, Member(root, "features", &json::is_array,
                                                   "the FeatureCollection", "an array"));
  if (features->empty()) return Status::InvalidArgument("the FeatureCollection has no features");
  for (size_t i = 0; i < features->size(); ++i) {
    TB_ASSIGN_OR_RETURN(MemoryFeature f, ReadFeature((*features)[i], reprojection,
                                                     "features[" + std::to_string(i) + "]"));
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace tinbase::service
