#include "core/vector/polygon_source.h"

#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>

#include "core/base/number_text.h"
#include "core/base/object_name.h"
#include "core/vector/gdal_session.h"

namespace tinbase {

namespace {

struct TransformDeleter {
  void operator()(OGRCoordinateTransformation* t) const {
    OGRCoordinateTransformation::DestroyCT(t);
  }
};

// One layer of an open source, with what every feature needs: the reprojection (null when
// coordinates stay as they are) and the tag field's index (-1 for none).
struct OpenLayer {
  GdalDatasetPtr dataset;
  OGRLayer* layer = nullptr;
  std::string name;  // the file's name, as messages show it
  std::unique_ptr<OGRCoordinateTransformation, TransformDeleter> transform;
  std::string transform_label;  // "from EPSG:4326 to EPSG:32631"
  int tag_index = -1;
};

std::string LayerNames(GDALDataset& ds) {
  std::string names;
  for (int i = 0; i < ds.GetLayerCount(); ++i)
    names += (i ? ", " : "") + std::string(ds.GetLayer(i)->GetName());
  return names;
}

std::string FieldNames(OGRFeatureDefn& defn) {
  std::string names;
  for (int i = 0; i < defn.GetFieldCount(); ++i)
    names += (i ? ", " : "") + std::string(defn.GetFieldDefn(i)->GetNameRef());
  return names;
}

Status SetUpTransform(OpenLayer& open, const VectorSourceOptions& options) {
  if (!options.target_crs) return Status::Ok();
  std::unique_ptr<OGRSpatialReference> source;
  if (const OGRSpatialReference* srs = open.layer->GetSpatialRef()) {
    source.reset(srs->Clone());
  } else if (options.assumed_source_crs) {
    source.reset(options.assumed_source_crs->ogr().Clone());
  } else {
    return Status::InvalidArgument(open.name +
                                   ": source has no CRS, so it cannot be reprojected to " +
                                   options.target_crs->Label() + " (name the source's CRS)");
  }
  source->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  char* wkt = nullptr;
  source->exportToWkt(&wkt);
  auto source_crs = Crs::FromWkt(wkt != nullptr ? wkt : "");
  CPLFree(wkt);
  if (!source_crs.ok()) return source_crs.status().WithContext(open.name);
  if (source_crs->IsSame(*options.target_crs)) return Status::Ok();
  open.transform.reset(
      OGRCreateCoordinateTransformation(&source_crs->ogr(), &options.target_crs->ogr()));
  open.transform_label = "from " + source_crs->Label() + " to " + options.target_crs->Label();
  if (!open.transform)
    return Status::InvalidArgument(open.name + ": no transformation " + open.transform_label +
                                   LastGdalError());
  return Status::Ok();
}

Result<OpenLayer> Open(const std::string& path, const VectorSourceOptions& options) {
  RegisterGdalDriversOnce();
  OpenLayer open;
  open.name = std::filesystem::path(path).filename().string();
  // GDAL's virtual paths (/vsizip/, /vsicurl/, ...) are not files to look for.
  std::error_code ec;
  if (path.rfind("/vsi", 0) != 0 && !std::filesystem::exists(path, ec))
    return Status::NotFound(path + ": no such file");
  open.dataset.reset(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  if (!open.dataset)
    return Status::InvalidArgument(path + ": not a vector source GDAL can read" + LastGdalError());
  GDALDataset& ds = *open.dataset;
  if (!options.layer.empty()) {
    open.layer = ds.GetLayerByName(options.layer.c_str());
    if (open.layer == nullptr)
      return Status::InvalidArgument(open.name + ": no layer named '" + options.layer +
                                     "' (layers: " + LayerNames(ds) + ")");
  } else if (ds.GetLayerCount() == 1) {
    open.layer = ds.GetLayer(0);
  } else if (ds.GetLayerCount() == 0) {
    return Status::InvalidArgument(open.name + ": source has no layers");
  } else {
    return Status::InvalidArgument(open.name + ": source has " +
                                   std::to_string(ds.GetLayerCount()) + " layers (" +
                                   LayerNames(ds) + "); name one");
  }
  OGRFeatureDefn& defn = *open.layer->GetLayerDefn();
  if (!options.tag_field.empty()) {
    open.tag_index = defn.GetFieldIndex(options.tag_field.c_str());
    if (open.tag_index < 0)
      return Status::InvalidArgument(open.name + ": layer '" + open.layer->GetName() +
                                     "' has no field named '" + options.tag_field +
                                     "' (fields: " + FieldNames(defn) + ")");
  }
  if (!options.where.empty() &&
      open.layer->SetAttributeFilter(options.where.c_str()) != OGRERR_NONE)
    return Status::InvalidArgument(open.name + ": bad attribute filter '" + options.where + "'" +
                                   LastGdalError());
  TB_RETURN_IF_ERROR(SetUpTransform(open, options));
  return open;
}

nlohmann::json FieldValue(const OGRFeature& feature, int i) {
  if (!feature.IsFieldSetAndNotNull(i)) return nullptr;
  const OGRFieldDefn& defn = *feature.GetFieldDefnRef(i);
  int count = 0;
  switch (defn.GetType()) {
    case OFTInteger:
      if (defn.GetSubType() == OFSTBoolean) return feature.GetFieldAsInteger(i) != 0;
      return feature.GetFieldAsInteger(i);
    case OFTInteger64:
      return static_cast<int64_t>(feature.GetFieldAsInteger64(i));
    case OFTReal:
      return feature.GetFieldAsDouble(i);
    case OFTIntegerList: {
      const int* values = feature.GetFieldAsIntegerList(i, &count);
      return nlohmann::json(std::vector<int>(values, values + count));
    }
    case OFTInteger64List: {
      const GIntBig* values = feature.GetFieldAsInteger64List(i, &count);
      return nlohmann::json(std::vector<int64_t>(values, values + count));
    }
    case OFTRealList: {
      const double* values = feature.GetFieldAsDoubleList(i, &count);
      return nlohmann::json(std::vector<double>(values, values + count));
    }
    case OFTStringList: {
      nlohmann::json list = nlohmann::json::array();
      for (char** s = feature.GetFieldAsStringList(i); s != nullptr && *s != nullptr; ++s)
        list.push_back(*s);
      return list;
    }
    default:
      return feature.GetFieldAsString(i);  // strings, dates and times as OGR prints them
  }
}

nlohmann::json Attributes(const OGRFeature& feature) {
  nlohmann::json out = nlohmann::json::object();
  for (int i = 0; i < feature.GetFieldCount(); ++i)
    out[feature.GetFieldDefnRef(i)->GetNameRef()] = FieldValue(feature, i);
  return out;
}

// Every coordinate a usable number (core/base/number_text.h): finite, and not beyond 1e15,
// which no CRS has room for and which would overflow the geometry's products.
Status CheckFinite(const std::vector<Point2>& points, const std::string& what) {
  for (size_t v = 0; v < points.size(); ++v) {
    const auto problem =
        CheckNumber(points[v].x) ? CheckNumber(points[v].x) : CheckNumber(points[v].y);
    if (problem == NumberProblem::kNotFinite)
      return Status::InvalidArgument(what + ", vertex " + std::to_string(v) +
                                     ": coordinate is not finite " + FormatPoint(points[v]));
    if (problem)
      return Status::InvalidArgument(what + ", vertex " + std::to_string(v) + ": coordinate " +
                                     FormatPoint(points[v]) + " " +
                                     DescribeNumberProblem(*problem));
  }
  return Status::Ok();
}

// The attributes as JSON text would hold them: a field name or text value that is not valid
// UTF-8 cannot be stored (or printed by `--json` later), so it is refused here, by name.
Status CheckAttributes(const nlohmann::json& attributes, const std::string& label) {
  for (const auto& [name, value] : attributes.items()) {
    try {
      (void)nlohmann::json{{name, value}}.dump();
    } catch (const nlohmann::json::exception&) {
      return Status::InvalidArgument(label + ", field '" + EscapedName(name) +
                                     "': the name or value is not valid UTF-8");
    }
  }
  return Status::Ok();
}

// Reads a curve's points and brings them into the target CRS. Non-finite input is reported
// as such before reprojection, which would only turn it into a vaguer failure.
Result<std::vector<Point2>> ReadPoints(const OpenLayer& open, const OGRSimpleCurve& curve,
                                       const std::string& what) {
  std::vector<Point2> points(curve.getNumPoints());
  for (int i = 0; i < curve.getNumPoints(); ++i) points[i] = {curve.getX(i), curve.getY(i)};
  if (!open.transform) return points;
  TB_RETURN_IF_ERROR(CheckFinite(points, what));
  std::vector<double> x(points.size()), y(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    x[i] = points[i].x;
    y[i] = points[i].y;
  }
  std::vector<int> ok(points.size(), 0);
  // The overall result is ignored: the per-point flags say which vertex failed.
  open.transform->Transform(static_cast<int>(points.size()), x.data(), y.data(), nullptr,
                            ok.data());
  for (size_t i = 0; i < points.size(); ++i) {
    if (!ok[i] || !std::isfinite(x[i]) || !std::isfinite(y[i]))
      return Status::InvalidArgument(what + ", vertex " + std::to_string(i) + ": " +
                                     FormatPoint(points[i]) + " cannot be reprojected " +
                                     open.transform_label);
    points[i] = {x[i], y[i]};
  }
  return points;
}

// Calls `visit(feature, fid, label)` for every feature that passes the filter. Finding none is
// the user's mistake, not a missing thing: InvalidArgument naming the file, layer and filter.
Status ForEachFeature(
    OpenLayer& open, const VectorSourceOptions& options,
    const std::function<Status(OGRFeature&, int64_t, const std::string&)>& visit) {
  int64_t index = 0;
  open.layer->ResetReading();
  for (auto& feature : *open.layer) {
    const int64_t fid = feature->GetFID() != OGRNullFID ? feature->GetFID() : index;
    Status visited = visit(*feature, fid, open.name + " feature " + std::to_string(fid));
    ++index;
    if (visited.ok()) continue;
    if (options.rejected == nullptr || visited.code() != StatusCode::kInvalidArgument)
      return visited;
    options.rejected->push_back(visited.message());
  }
  if (index == 0) {
    std::string msg = open.name + ": no features in layer '" + open.layer->GetName() + "'";
    if (!options.where.empty()) msg += " match filter '" + options.where + "'";
    return Status::InvalidArgument(msg);
  }
  return Status::Ok();
}

// The feature's geometry with curves replaced by line segments; `owned` keeps a linearised
// copy alive. Error when the feature has none.
Result<const OGRGeometry*> LinearGeometry(const OGRFeature& feature, const std::string& label,
                                          std::unique_ptr<OGRGeometry>& owned) {
  const OGRGeometry* g = feature.GetGeometryRef();
  if (g == nullptr || g->IsEmpty())
    return Status::InvalidArgument(label + ": feature has no geometry");
  if (OGR_GT_IsNonLinear(g->getGeometryType())) {
    owned.reset(g->getLinearGeometry());
    g = owned.get();
  }
  return g;
}

// GEOS MakeValid of `g`, with only its polygonal parts: a collapsed piece of a ring comes back
// as a line or point, which a polygon feature cannot use.
Result<std::unique_ptr<OGRGeometry>> Repaired(const OGRGeometry& g, const std::string& label) {
  std::unique_ptr<OGRGeometry> fixed(g.MakeValid());
  if (fixed == nullptr)
    return Status::InvalidArgument(label + ": cannot repair the geometry (GDAL without GEOS?)");
  if (wkbFlatten(fixed->getGeometryType()) != wkbGeometryCollection) return fixed;
  auto polygons = std::make_unique<OGRMultiPolygon>();
  for (const OGRGeometry* part : *fixed->toGeometryCollection()) {
    if (wkbFlatten(part->getGeometryType()) == wkbPolygon) polygons->addGeometry(part);
    if (wkbFlatten(part->getGeometryType()) == wkbMultiPolygon)
      for (const OGRPolygon* p : *part->toMultiPolygon()) polygons->addGeometry(p);
  }
  if (polygons->IsEmpty())
    return Status::InvalidArgument(label + ": nothing of the polygon is left after repair");
  return std::unique_ptr<OGRGeometry>(std::move(polygons));
}

template <typename Feature>
Status FillCommon(Feature& out, const OGRFeature& feature, int64_t fid, const std::string& label,
                  const OpenLayer& open) {
  out.fid = fid;
  out.label = label;
  out.attributes = Attributes(feature);
  TB_RETURN_IF_ERROR(CheckAttributes(out.attributes, label));
  if (open.tag_index >= 0 && feature.IsFieldSetAndNotNull(open.tag_index))
    out.tag = feature.GetFieldAsString(open.tag_index);
  return Status::Ok();
}

Result<Polygon> ReadPolygon(const OpenLayer& open, const OGRPolygon& polygon,
                            const std::string& prefix) {
  std::vector<Ring> rings;
  for (int r = 0; r <= polygon.getNumInteriorRings(); ++r) {
    const OGRLinearRing* ring = r == 0 ? polygon.getExteriorRing() : polygon.getInteriorRing(r - 1);
    TB_ASSIGN_OR_RETURN(Ring points, ReadPoints(open, *ring, prefix + "ring " + std::to_string(r)));
    rings.push_back(std::move(points));
  }
  auto valid = MakeValidPolygon(rings);
  if (!valid.ok()) return Status::InvalidArgument(prefix + valid.status().message());
  return valid;
}

}  // namespace

Result<std::vector<PolygonFeature>> ReadPolygonFeatures(const std::string& path,
                                                        const VectorSourceOptions& options) {
  QuietGdalErrors quiet;
  TB_ASSIGN_OR_RETURN(OpenLayer open, Open(path, options));
  std::vector<PolygonFeature> features;
  TB_RETURN_IF_ERROR(ForEachFeature(
      open, options, [&](OGRFeature& feature, int64_t fid, const std::string& label) -> Status {
        std::unique_ptr<OGRGeometry> owned;
        TB_ASSIGN_OR_RETURN(const OGRGeometry* g, LinearGeometry(feature, label, owned));
        if (options.repair) {
          TB_ASSIGN_OR_RETURN(owned, Repaired(*g, label));
          g = owned.get();
        }
        std::vector<const OGRPolygon*> parts;
        switch (wkbFlatten(g->getGeometryType())) {
          case wkbPolygon:
            parts.push_back(g->toPolygon());
            break;
          case wkbMultiPolygon:
            for (const OGRPolygon* part : *g->toMultiPolygon()) parts.push_back(part);
            break;
          default:
            return Status::InvalidArgument(label + ": geometry is a " +
                                           OGRGeometryTypeToName(g->getGeometryType()) +
                                           ", not a Polygon or MultiPolygon");
        }
        PolygonFeature out;
        TB_RETURN_IF_ERROR(FillCommon(out, feature, fid, label, open));
        for (size_t p = 0; p < parts.size(); ++p) {
          const std::string prefix =
              label + (parts.size() > 1 ? ", polygon " + std::to_string(p) : "") + ", ";
          if (parts[p]->IsEmpty()) return Status::InvalidArgument(prefix + "polygon is empty");
          TB_ASSIGN_OR_RETURN(Polygon polygon, ReadPolygon(open, *parts[p], prefix));
          out.polygons.push_back(std::move(polygon));
        }
        features.push_back(std::move(out));
        return Status::Ok();
      }));
  return features;
}

Result<std::vector<LineFeature>> ReadLineFeatures(const std::string& path,
                                                  const VectorSourceOptions& options) {
  QuietGdalErrors quiet;
  TB_ASSIGN_OR_RETURN(OpenLayer open, Open(path, options));
  std::vector<LineFeature> features;
  TB_RETURN_IF_ERROR(ForEachFeature(
      open, options, [&](OGRFeature& feature, int64_t fid, const std::string& label) -> Status {
        std::unique_ptr<OGRGeometry> owned;
        TB_ASSIGN_OR_RETURN(const OGRGeometry* g, LinearGeometry(feature, label, owned));
        std::vector<const OGRLineString*> parts;
        switch (wkbFlatten(g->getGeometryType())) {
          case wkbLineString:
            parts.push_back(g->toLineString());
            break;
          case wkbMultiLineString:
            for (const OGRLineString* part : *g->toMultiLineString()) parts.push_back(part);
            break;
          default:
            return Status::InvalidArgument(label + ": geometry is a " +
                                           OGRGeometryTypeToName(g->getGeometryType()) +
                                           ", not a LineString or MultiLineString");
        }
        LineFeature out;
        TB_RETURN_IF_ERROR(FillCommon(out, feature, fid, label, open));
        out.has_z = !parts.empty();
        for (size_t k = 0; k < parts.size(); ++k) {
          const std::string what = label + ", line " + std::to_string(k);
          TB_ASSIGN_OR_RETURN(std::vector<Point2> raw, ReadPoints(open, *parts[k], what));
          TB_RETURN_IF_ERROR(CheckFinite(raw, what));
          std::vector<Point2> line;
          std::vector<double> z;
          const bool has_z = parts[k]->Is3D();
          out.has_z = out.has_z && has_z;
          for (size_t i = 0; i < raw.size(); ++i) {
            if (!line.empty() && SamePoint(line.back(), raw[i])) continue;
            line.push_back(raw[i]);
            z.push_back(has_z ? parts[k]->getZ(static_cast<int>(i)) : std::nan(""));
          }
          if (line.size() < 2)
            return Status::InvalidArgument(what + ": fewer than 2 distinct points");
          out.lines.push_back(std::move(line));
          out.z.push_back(std::move(z));
        }
        features.push_back(std::move(out));
        return Status::Ok();
      }));
  return features;
}

Result<std::optional<Crs>> ReadVectorCrs(const std::string& path,
                                         const VectorSourceOptions& options) {
  QuietGdalErrors quiet;
  VectorSourceOptions as_stored = options;
  as_stored.target_crs.reset();
  as_stored.assumed_source_crs.reset();
  TB_ASSIGN_OR_RETURN(OpenLayer open, Open(path, as_stored));
  const OGRSpatialReference* srs = open.layer->GetSpatialRef();
  if (srs == nullptr) return std::optional<Crs>();
  char* wkt = nullptr;
  srs->exportToWkt(&wkt);
  auto crs = Crs::FromWkt(wkt != nullptr ? wkt : "");
  CPLFree(wkt);
  if (!crs.ok()) return crs.status().WithContext(open.name);
  return std::optional<Crs>(std::move(crs).value());
}

}  // namespace tinbase
