// GeoJSON request bodies: JSON checked shape by shape, reprojected, then validated as the
// editor's polygons and lines.
#include "service/geojson_request.h"

#include <ogr_spatialref.h>

#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "core/base/message_text.h"
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

// A position as read: x and y, and z when it has a third number.
struct Position {
  Point2 xy;
  double z = 0;
  bool has_z = false;
};

// The points of a ring, line or multipoint: positions of 2 or 3 finite numbers, reprojected (z
// with them, where there is one).
Result<std::vector<Position>> ReadPositions(const json& positions, const Reprojection& reprojection,
                                            const std::string& what) {
  if (!positions.is_array())
    return Status::InvalidArgument(what + ": coordinates are " + TypeName(positions) +
                                   ", not an array of positions");
  std::vector<Position> points;
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
    Position read{{p[0].get<double>(), p[1].get<double>()}, 0, p.size() == 3};
    if (read.has_z) read.z = p[2].get<double>();
    points.push_back(read);
  }
  if (!reprojection.transform) return points;
  std::vector<double> x(points.size()), y(points.size()), z(points.size());
  for (size_t i = 0; i < points.size(); ++i)
    x[i] = points[i].xy.x, y[i] = points[i].xy.y, z[i] = points[i].z;
  std::vector<int> ok(points.size(), 0);
  // The overall result is ignored: the per-point flags say which vertex failed.
  reprojection.transform->Transform(static_cast<int>(points.size()), x.data(), y.data(), z.data(),
                                    ok.data());
  for (size_t i = 0; i < points.size(); ++i) {
    const bool z_ok = !points[i].has_z || std::isfinite(z[i]);
    if (!ok[i] || !std::isfinite(x[i]) || !std::isfinite(y[i]) || !z_ok)
      return Status::InvalidArgument(what + ", vertex " + std::to_string(i) + ": " +
                                     FormatPoint(points[i].xy) + " cannot be reprojected " +
                                     reprojection.label);
    points[i].xy = {x[i], y[i]};
    if (points[i].has_z) points[i].z = z[i];
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
        std::vector<Position> ring,
        ReadPositions(rings[r], reprojection, prefix + "ring " + std::to_string(r)));
    read.emplace_back();
    for (const Position& p : ring) read.back().push_back(p.xy);
  }
  auto valid = MakeValidPolygon(read);
  if (!valid.ok()) return Status::InvalidArgument(prefix + valid.status().message());
  return valid;
}

// One line into out->lines, consecutive repeats dropped (the first one's z kept); at least 2
// distinct points. Its z goes into out->line_z when every vertex has one, else an empty entry
// (a line with z from the feature is then refused by the editor, naming the line).
Status ReadLine(const json& positions, const Reprojection& reprojection, const std::string& what,
                MemoryFeature* out) {
  TB_ASSIGN_OR_RETURN(std::vector<Position> points, ReadPositions(positions, reprojection, what));
  std::vector<Point2> line;
  std::vector<double> z;
  bool all_z = true;
  for (const Position& p : points) {
    if (!line.empty() && SamePoint(line.back(), p.xy)) continue;
    line.push_back(p.xy);
    z.push_back(p.z);
    all_z = all_z && p.has_z;
  }
  if (line.size() < 2)
    return Status::InvalidArgument(what + ": a line needs at least 2 distinct points");
  out->lines.push_back(std::move(line));
  out->line_z.push_back(all_z ? std::move(z) : std::vector<double>{});
  return Status::Ok();
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
    TB_RETURN_IF_ERROR(ReadLine(*coordinates, reprojection, prefix + "line 0", out));
  } else if (kind == "MultiLineString") {
    for (size_t k = 0; k < coordinates->size(); ++k) {
      TB_RETURN_IF_ERROR(
          ReadLine((*coordinates)[k], reprojection, prefix + "line " + std::to_string(k), out));
    }
  } else {
    return Status::InvalidArgument(label + ": geometry is a " + OneLineText(kind) +
                                   "; a Polygon, MultiPolygon, LineString or MultiLineString "
                                   "is needed");
  }
  if (out->polygons.empty() && out->lines.empty())
    return Status::InvalidArgument(label + ": the geometry is empty");
  return Status::Ok();
}

// properties.mode, .tag, .level and .z_from into `out`; the other properties become its attributes.
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
    } else if (key == "z_from" && !value.is_null()) {
      if (!value.is_string())
        return Status::InvalidArgument(label + ": properties.z_from is " + TypeName(value) +
                                       ", not a string");
      auto z_from = ParseZFrom(value.get<std::string>());
      if (!z_from.ok()) return z_from.status().WithContext(label + ": properties.z_from");
      out->z_from = *z_from;
    } else if (key != "mode" && key != "tag" && key != "level" && key != "z_from") {
      out->attributes[key] = value;
    }
  }
  return Status::Ok();
}

// InvalidArgument unless `feature` is a GeoJSON Feature object.
Status CheckFeatureObject(const json& feature, const std::string& label) {
  if (!feature.is_object())
    return Status::InvalidArgument(label + " is " + TypeName(feature) + ", not a Feature object");
  TB_ASSIGN_OR_RETURN(const json* type,
                      Member(feature, "type", &json::is_string, label, "a string"));
  if (*type != "Feature")
    return Status::InvalidArgument(label + ": type is \"" + OneLineText(type->get<std::string>()) +
                                   "\", not \"Feature\"");
  return Status::Ok();
}

Result<MemoryFeature> ReadFeature(const json& feature, const Reprojection& reprojection,
                                  const std::string& label) {
  TB_RETURN_IF_ERROR(CheckFeatureObject(feature, label));
  MemoryFeature out;
  out.label = label;
  TB_RETURN_IF_ERROR(ReadProperties(feature, label, &out));
  TB_RETURN_IF_ERROR(ReadGeometry(feature, reprojection, label, &out));
  return out;
}

// The survey points of one Feature (a Point or MultiPoint whose positions all have z) appended to
// `out`, each labelled "<label>, point k".
Status ReadSurveyPoints(const json& feature, const Reprojection& reprojection,
                        const std::string& label, SurveyPointsBody* out) {
  TB_RETURN_IF_ERROR(CheckFeatureObject(feature, label));
  const auto it = feature.find("geometry");
  if (it == feature.end() || it->is_null())
    return Status::InvalidArgument(label + ": the feature has no geometry");
  if (!it->is_object())
    return Status::InvalidArgument(label + ": geometry is " + TypeName(*it) + ", not an object");
  TB_ASSIGN_OR_RETURN(const json* type,
                      Member(*it, "type", &json::is_string, label + ", geometry", "a string"));
  TB_ASSIGN_OR_RETURN(const json* coordinates, Member(*it, "coordinates", &json::is_array,
                                                      label + ", geometry", "an array"));
  std::vector<Position> points;
  if (*type == "Point") {
    TB_ASSIGN_OR_RETURN(points, ReadPositions(json::array({*coordinates}), reprojection, label));
  } else if (*type == "MultiPoint") {
    TB_ASSIGN_OR_RETURN(points, ReadPositions(*coordinates, reprojection, label));
  } else {
    return Status::InvalidArgument(label + ": geometry is a " +
                                   OneLineText(type->get<std::string>()) +
                                   "; survey points are a Point or MultiPoint (with z)");
  }
  if (points.empty()) return Status::InvalidArgument(label + ": the geometry is empty");
  for (size_t k = 0; k < points.size(); ++k) {
    const std::string where = label + ", point " + std::to_string(k);
    if (!points[k].has_z)
      return Status::InvalidArgument(where + ": " + FormatPoint(points[k].xy) +
                                     " has no z (a survey point is x, y, z)");
    TinVertex v;
    v.x = points[k].xy.x;
    v.y = points[k].xy.y;
    v.z = points[k].z;
    out->points.push_back(v);
    out->labels.push_back(where);
  }
  return Status::Ok();
}

// "[json.exception.parse_error.101] parse error at line 1, column 9: ..." without its bracket.
std::string ParseErrorText(const json::exception& e) {
  std::string text = e.what();
  const size_t close = text.find("] ");
  return close == std::string::npos ? text : text.substr(close + 2);
}

// Calls read(feature, label) for the Feature `body` is ("feature") or for each of the
// FeatureCollection's ("features[2]"), in order, until one fails.
template <typename Read>
Status ForEachBodyFeature(std::string_view body, const Read& read) {
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
  if (*type == "Feature") return read(root, std::string("feature"));
  if (*type != "FeatureCollection")
    return Status::InvalidArgument("the body is a GeoJSON \"" +
                                   OneLineText(type->get<std::string>()) +
                                   "\"; a Feature or FeatureCollection is needed");
  TB_ASSIGN_OR_RETURN(const json* features, Member(root, "features", &json::is_array,
                                                   "the FeatureCollection", "an array"));
  if (features->empty()) return Status::InvalidArgument("the FeatureCollection has no features");
  for (size_t i = 0; i < features->size(); ++i)
    TB_RETURN_IF_ERROR(read((*features)[i], "features[" + std::to_string(i) + "]"));
  return Status::Ok();
}

}  // namespace

Result<std::vector<MemoryFeature>> ParseGeoJsonFeatures(std::string_view body,
                                                        const std::optional<Crs>& source_crs,
                                                        const Crs& store_crs) {
  QuietGdalErrors quiet;  // a point PROJ cannot transform is the client's, reported as a Status
  TB_ASSIGN_OR_RETURN(Reprojection reprojection, MakeReprojection(source_crs, store_crs));
  std::vector<MemoryFeature> out;
  TB_RETURN_IF_ERROR(
      ForEachBodyFeature(body, [&](const json& feature, const std::string& label) -> Status {
        TB_ASSIGN_OR_RETURN(MemoryFeature f, ReadFeature(feature, reprojection, label));
        out.push_back(std::move(f));
        return Status::Ok();
      }));
  return out;
}

Result<SurveyPointsBody> ParseGeoJsonPoints(std::string_view body,
                                            const std::optional<Crs>& source_crs,
                                            const Crs& store_crs) {
  QuietGdalErrors quiet;
  TB_ASSIGN_OR_RETURN(Reprojection reprojection, MakeReprojection(source_crs, store_crs));
  SurveyPointsBody out;
  TB_RETURN_IF_ERROR(ForEachBodyFeature(body, [&](const json& feature, const std::string& label) {
    return ReadSurveyPoints(feature, reprojection, label, &out);
  }));
  return out;
}

}  // namespace tinbase::service
