#include "core/export/geojson_writer.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <filesystem>
#include <memory>
#include <system_error>

#include "core/vector/gdal_session.h"

namespace tinbase {

Status WriteGeoJson(const Tin& tin, const Crs* crs, const MeshSelection& s,
                    const std::vector<int64_t>& ids, const std::string& path) {
  RegisterGdalDriversOnce();
  QuietGdalErrors quiet;
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GeoJSON");
  if (driver == nullptr) return Status::IOError(path + ": GDAL has no GeoJSON driver");
  // The driver refuses to overwrite; an export replaces what was there, as the OBJ writer does.
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec)) std::filesystem::remove(path, ec);
  GdalDatasetPtr ds(driver->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  if (!ds) return Status::IOError(path + ": cannot create GeoJSON file" + LastGdalError());

  std::unique_ptr<OGRSpatialReference> srs;
  if (crs != nullptr) srs = std::make_unique<OGRSpatialReference>(crs->ogr());
  const char* layer_options[] = {"RFC7946=NO", "SIGNIFICANT_FIGURES=17", "WRITE_BBOX=NO", nullptr};
  OGRLayer* layer =
      ds->CreateLayer("triangles", srs.get(), wkbPolygon25D, const_cast<char**>(layer_options));
  if (layer == nullptr) return Status::IOError(path + ": cannot create layer" + LastGdalError());
  OGRFieldDefn id_field("id", OFTInteger64);
  OGRFieldDefn visible_field("visible", OFTInteger);
  visible_field.SetSubType(OFSTBoolean);
  OGRFieldDefn tag_field("tag", OFTString);
  for (OGRFieldDefn* field : {&id_field, &visible_field, &tag_field}) {
    if (layer->CreateField(field) != OGRERR_NONE)
      return Status::IOError(path + ": cannot create field '" + field->GetNameRef() + "'");
  }

  for (uint32_t t : s.triangles) {
    const TinTriangle& tri = tin.triangles[t];
    OGRFeature feature(layer->GetLayerDefn());
    feature.SetField(0, static_cast<GIntBig>(ids.empty() ? int64_t{t} : ids[t]));
    feature.SetField(1, tri.visible ? 1 : 0);
    if (tri.tag != kNoTag) {
      feature.SetField(2, tin.tags[static_cast<size_t>(tri.tag)].c_str());
    } else {
      feature.SetFieldNull(2);
    }
    auto ring = std::make_unique<OGRLinearRing>();
    for (int i = 0; i <= 3; ++i) {
      const TinVertex& p = tin.vertices[tri.v[i % 3]];
      ring->addPoint(p.x, p.y, p.z);
    }
    auto polygon = std::make_unique<OGRPolygon>();
    polygon->addRingDirectly(ring.release());
    feature.SetGeometryDirectly(polygon.release());
    if (layer->CreateFeature(&feature) != OGRERR_NONE)
      return Status::IOError(path + ": cannot write triangle " + std::to_string(t) +
                             LastGdalError());
  }
  // GDAL 3.6's GDALClose returns nothing; a failed final write shows as the last error.
  CPLErrorReset();
  ds.reset();
  if (CPLGetLastErrorType() >= CE_Failure)
    return Status::IOError(path + ": cannot finish GeoJSON file" + LastGdalError());
  return Status::Ok();
}

}  // namespace tinbase
