#include "core/export/tin_export.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <cassert>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <system_error>

#include "core/vector/gdal_session.h"

namespace tinbase {

namespace {

// The triangles to write and the vertices they use, renumbered densely in first-use order when
// invisible triangles are dropped (so an exported file never carries orphan vertices).
struct Selection {
  std::vector<uint32_t> triangles;    // indices into tin.triangles
  std::vector<uint32_t> vertices;     // indices into tin.vertices, in output order
  std::vector<int64_t> output_index;  // tin vertex -> output position, -1 when dropped
};

Selection Select(const Tin& tin, bool visible_only) {
  Selection s;
  s.output_index.assign(tin.vertices.size(), -1);
  if (!visible_only) {
    s.triangles.resize(tin.triangles.size());
    for (size_t t = 0; t < tin.triangles.size(); ++t) s.triangles[t] = static_cast<uint32_t>(t);
    s.vertices.resize(tin.vertices.size());
    for (size_t v = 0; v < tin.vertices.size(); ++v) {
      s.vertices[v] = static_cast<uint32_t>(v);
      s.output_index[v] = static_cast<int64_t>(v);
    }
    return s;
  }
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    if (!tri.visible) continue;
    s.triangles.push_back(static_cast<uint32_t>(t));
    for (uint32_t v : tri.v) {
      if (s.output_index[v] >= 0) continue;
      s.output_index[v] = static_cast<int64_t>(s.vertices.size());
      s.vertices.push_back(v);
    }
  }
  return s;
}

// Shortest text that reads back as exactly `value` (std::to_chars without a precision).
void AppendNumber(std::string& out, double value) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, ec == std::errc() ? end : buffer);
}

std::string OneLineWkt(const Crs& crs) {
  char* wkt = nullptr;
  const char* options[] = {"FORMAT=WKT2_2018", "MULTILINE=NO", nullptr};
  crs.ogr().exportToWkt(&wkt, options);
  std::string out = wkt != nullptr ? wkt : "";
  CPLFree(wkt);
  return out;
}

Status WriteObj(const Tin& tin, const Crs* crs, const std::string& path, const Selection& s) {
  std::string text =
      "# tinbase surface (Wavefront OBJ): x y z per vertex, faces counter-clockwise "
      "seen from above\n";
  if (crs != nullptr) {
    text += "# crs: " + crs->Label() + "\n# crs_wkt: " + OneLineWkt(*crs) + "\n";
  } else {
    text += "# crs: none\n";
  }
  text += "# vertices: " + std::to_string(s.vertices.size()) +
          ", triangles: " + std::to_string(s.triangles.size()) + "\n";
  text.reserve(text.size() + s.vertices.size() * 64 + s.triangles.size() * 32);
  for (uint32_t v : s.vertices) {
    const TinVertex& p = tin.vertices[v];
    text += "v ";
    AppendNumber(text, p.x);
    text += ' ';
    AppendNumber(text, p.y);
    text += ' ';
    AppendNumber(text, p.z);
    text += '\n';
  }
  for (uint32_t t : s.triangles) {
    text += 'f';
    for (uint32_t v : tin.triangles[t].v) text += ' ' + std::to_string(s.output_index[v] + 1);
    text += '\n';
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return Status::IOError(path + ": cannot open for writing");
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) return Status::IOError(path + ": write failed");
  return Status::Ok();
}

Status WriteGeoJson(const Tin& tin, const Crs* crs, const std::string& path, const Selection& s,
                    const std::vector<int64_t>& ids) {
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
  // RFC7946 would force WGS 84 longitude/latitude; projected surfaces must keep their
  // coordinates. 17 significant figures make every double read back exactly.
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

}  // namespace

Result<ExportFormat> ParseExportFormat(const std::string& name) {
  if (name == "obj") return ExportFormat::kObj;
  if (name == "geojson") return ExportFormat::kGeoJson;
  return Status::InvalidArgument("unknown export format '" + name + "' (expected obj or geojson)");
}

Result<ExportReport> ExportTin(const Tin& tin, const Crs* crs, const std::string& path,
                               const ExportOptions& options) {
  if (!options.triangle_ids.empty() && options.triangle_ids.size() != tin.triangles.size())
    return Status::InvalidArgument(path + ": " + std::to_string(options.triangle_ids.size()) +
                                   " triangle ids for " + std::to_string(tin.triangles.size()) +
                                   " triangles");
#ifndef NDEBUG
  for (const TinTriangle& tri : tin.triangles) {
    for (uint32_t v : tri.v) assert(v < tin.vertices.size());
    assert(tri.tag == kNoTag || (tri.tag >= 0 && static_cast<size_t>(tri.tag) < tin.tags.size()));
  }
#endif
  const Selection selection = Select(tin, options.visible_only);
  switch (options.format) {
    case ExportFormat::kObj:
      TB_RETURN_IF_ERROR(WriteObj(tin, crs, path, selection));
      break;
    case ExportFormat::kGeoJson:
      TB_RETURN_IF_ERROR(WriteGeoJson(tin, crs, path, selection, options.triangle_ids));
      break;
  }
  ExportReport report;
  report.vertices = static_cast<int64_t>(selection.vertices.size());
  report.triangles = static_cast<int64_t>(selection.triangles.size());
  return report;
}

}  // namespace tinbase
