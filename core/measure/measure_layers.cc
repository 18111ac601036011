#include "core/measure/measure_layers.h"

#include <ogrsf_frmts.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <system_error>

#include "core/base/output_file.h"
#include "core/vector/gdal_session.h"

namespace tinbase {

namespace {

namespace fs = std::filesystem;

std::string LowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

const char* DriverName(LayerFormat format) {
  switch (format) {
    case LayerFormat::kGeoPackage:
      return "GPKG";
    case LayerFormat::kGeoJson:
      return "GeoJSON";
    case LayerFormat::kShapefile:
      return "ESRI Shapefile";
  }
  return "";
}

struct FieldSpec {
  const char* name;
  OGRFieldType type;
};

// Fills the layer's features; returns an error to abandon the file.
using LayerFiller = std::function<Status(OGRLayer& layer)>;

// Creates `dataset_path` with one layer and lets `fill` write its features.
Status WriteDataset(LayerFormat format, const std::string& dataset_path, const std::string& label,
                    const std::string& layer_name, OGRwkbGeometryType type,
                    const std::vector<FieldSpec>& fields, const Crs* crs, const LayerFiller& fill) {
  RegisterGdalDriversOnce();
  QuietGdalErrors quiet;
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(DriverName(format));
  if (driver == nullptr)
    return Status::IOError(label + ": GDAL has no " + DriverName(format) + " driver");
  GdalDatasetPtr ds(driver->Create(dataset_path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  if (!ds) return Status::IOError(label + ": cannot create" + LastGdalError());
  std::unique_ptr<OGRSpatialReference> srs;
  if (crs != nullptr) {
    srs = std::make_unique<OGRSpatialReference>(crs->ogr());
    srs->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  }
  OGRLayer* layer = ds->CreateLayer(layer_name.c_str(), srs.get(), type, nullptr);
  if (layer == nullptr) return Status::IOError(label + ": cannot create a layer" + LastGdalError());
  for (const FieldSpec& f : fields) {
    OGRFieldDefn defn(f.name, f.type);
    if (layer->CreateField(&defn) != OGRERR_NONE)
      return Status::IOError(label + ": cannot create field " + f.name + LastGdalError());
  }
  // One transaction where the driver has them (GeoPackage): a row per feature otherwise.
  const bool transaction = ds->StartTransaction() == OGRERR_NONE;
  TB_RETURN_IF_ERROR(fill(*layer));
  if (transaction && ds->CommitTransaction() != OGRERR_NONE)
    return Status::IOError(label + ": cannot write" + LastGdalError());
  CPLErrorReset();
  ds.reset();
  if (CPLGetLastErrorType() >= CE_Failure)
    return Status::IOError(label + ": cannot finish writing" + LastGdalError());
  return Status::Ok();
}

// A shapefile: written as <stem>.* in a fresh directory beside `path`, then moved into place.
Status WriteShapefile(const std::string& path, const std::string& layer_name,
                      OGRwkbGeometryType type, const std::vector<FieldSpec>& fields, const Crs* crs,
                      const LayerFiller& fill) {
  TB_ASSIGN_OR_RETURN(OutputFile check, OutputFile::Create(path));  // writable directory
  const fs::path target(path);
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  const fs::path stage =
      dir / (".tinbase-" + target.stem().string() + "-" + std::to_string(::getpid()));
  std::error_code ec;
  fs::remove_all(stage, ec);
  if (!fs::create_directory(stage, ec))
    return Status::IOError(path + ": cannot create a temporary directory: " + ec.message());
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ignored;
      fs::remove_all(dir, ignored);
    }
  } cleanup{stage};
  const fs::path staged = stage / target.filename();
  TB_RETURN_IF_ERROR(WriteDataset(LayerFormat::kShapefile, staged.string(), path, layer_name, type,
                                  fields, crs, fill));
  // The sidecars first and the .shp last, so a reader never sees a .shp without its parts.
  std::vector<fs::path> parts;
  for (const auto& entry : fs::directory_iterator(stage)) parts.push_back(entry.path());
  std::sort(parts.begin(), parts.end(), [](const fs::path& a, const fs::path& b) {
    const bool a_shp = LowerExtension(a.string()) == ".shp";
    const bool b_shp = LowerExtension(b.string()) == ".shp";
    return a_shp != b_shp ? b_shp : a < b;
  });
  for (const fs::path& part : parts) {
    fs::rename(part, dir / part.filename(), ec);
    if (ec)
      return Status::IOError(path + ": cannot move " + part.filename().string() + ": " +
                             ec.message());
  }
  return Status::Ok();
}

Status WriteLayer(const std::string& path, const std::string& layer_name, OGRwkbGeometryType type,
                  const std::vector<FieldSpec>& fields, const Crs* crs, const LayerFiller& fill) {
  TB_ASSIGN_OR_RETURN(LayerFormat format, LayerFormatForPath(path));
  if (format == LayerFormat::kShapefile)
    return WriteShapefile(path, layer_name, type, fields, crs, fill);
  TB_ASSIGN_OR_RETURN(OutputFile out, OutputFile::Create(path));
  TB_RETURN_IF_ERROR(
      WriteDataset(format, out.temp_path(), path, layer_name, type, fields, crs, fill));
  return out.Commit();
}

Status AddFeature(OGRLayer& layer, OGRFeature& feature) {
  if (layer.CreateFeature(&feature) != OGRERR_NONE)
    return Status::IOError("cannot write a feature" + LastGdalError());
  return Status::Ok();
}

}  // namespace

Result<LayerFormat> LayerFormatForPath(const std::string& path) {
  const std::string ext = LowerExtension(path);
  if (ext == ".gpkg") return LayerFormat::kGeoPackage;
  if (ext == ".geojson" || ext == ".json") return LayerFormat::kGeoJson;
  if (ext == ".shp") return LayerFormat::kShapefile;
  return Status::InvalidArgument("unknown format for " + path +
                                 ": the extension must be .gpkg, .geojson, .json or .shp");
}

Status WriteContourLayer(const std::vector<ContourLine>& lines, const Crs* crs,
                         const std::string& path) {
  const std::vector<FieldSpec> fields = {{"id", OFTInteger64}, {"elevation", OFTReal}};
  return WriteLayer(path, "contours", wkbLineString25D, fields, crs, [&](OGRLayer& layer) {
    int64_t id = 0;
    for (const ContourLine& line : lines) {
      OGRFeature feature(layer.GetLayerDefn());
      feature.SetField("id", static_cast<GIntBig>(++id));
      feature.SetField("elevation", line.level);
      auto geometry = std::make_unique<OGRLineString>();
      for (const Point2& p : line.points) geometry->addPoint(p.x, p.y, line.level);
      if (line.closed) geometry->addPoint(line.points[0].x, line.points[0].y, line.level);
      feature.SetGeometryDirectly(geometry.release());
      TB_RETURN_IF_ERROR(AddFeature(layer, feature).WithContext(path));
    }
    return Status::Ok();
  });
}

Status WriteSlopeLayer(const Tin& tin, const std::vector<TriangleSlope>& slopes,
                       const std::vector<int64_t>& triangle_ids, const Crs* crs,
                       const std::string& path) {
  const std::vector<FieldSpec> fields = {{"triangle", OFTInteger64},
                                         {"slope_deg", OFTReal},
                                         {"aspect_deg", OFTReal},
                                         {"tag", OFTString}};
  return WriteLayer(path, "slope", wkbPolygon25D, fields, crs, [&](OGRLayer& layer) {
    for (const TriangleSlope& s : slopes) {
      const TinTriangle& t = tin.triangles[s.triangle];
      OGRFeature feature(layer.GetLayerDefn());
      feature.SetField("triangle", static_cast<GIntBig>(triangle_ids[s.triangle]));
      feature.SetField("slope_deg", s.slope_degrees);
      if (s.aspect_degrees) {
        feature.SetField("aspect_deg", *s.aspect_degrees);
      } else {
        feature.SetFieldNull(feature.GetFieldIndex("aspect_deg"));
      }
      if (t.tag >= 0 && static_cast<size_t>(t.tag) < tin.tags.size()) {
        feature.SetField("tag", tin.tags[static_cast<size_t>(t.tag)].c_str());
      } else {
        feature.SetFieldNull(feature.GetFieldIndex("tag"));
      }
      auto ring = std::make_unique<OGRLinearRing>();
      for (int i = 0; i <= 3; ++i) {
        const TinVertex& v = tin.vertices[t.v[i % 3]];
        ring->addPoint(v.x, v.y, v.z);
      }
      auto polygon = std::make_unique<OGRPolygon>();
      polygon->addRingDirectly(ring.release());
      feature.SetGeometryDirectly(polygon.release());
      TB_RETURN_IF_ERROR(AddFeature(layer, feature).WithContext(path));
    }
    return Status::Ok();
  });
}

}  // namespace tinbase
