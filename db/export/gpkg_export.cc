#include "db/export/gpkg_export.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/base/output_file.h"
#include "core/vector/feature_wkb.h"
#include "core/vector/gdal_session.h"
#include "db/dem_store.h"
#include "db/feature_store.h"
#include "db/mesh/mesh_tables.h"

namespace tinbase {

namespace {

// IOError "path: what (GDAL's last message)".
Status GdalFailure(const std::string& path, const std::string& what) {
  return Status::IOError(path + ": " + what + LastGdalError());
}

// An attribute column of a layer.
struct FieldSpec {
  const char* name;
  OGRFieldType type;
  OGRFieldSubType subtype = OFSTNone;
};

// Creates layer `name` with the FID column `fid` and the columns `fields`.
Result<OGRLayer*> CreateLayer(GDALDataset& ds, const std::string& path, const char* name,
                              const OGRSpatialReference* srs, OGRwkbGeometryType type,
                              const char* fid, const std::vector<FieldSpec>& fields) {
  // GDAL's default R*Tree spatial index stays on: readers such as QGIS draw a window through
  // it instead of reading every triangle.
  std::string fid_option = std::string("FID=") + fid;
  const char* options[] = {fid_option.c_str(), nullptr};
  OGRLayer* layer = ds.CreateLayer(name, const_cast<OGRSpatialReference*>(srs), type,
                                   const_cast<char**>(options));
  if (layer == nullptr) return GdalFailure(path, std::string("cannot create layer ") + name);
  for (const FieldSpec& spec : fields) {
    OGRFieldDefn field(spec.name, spec.type);
    field.SetSubType(spec.subtype);
    if (layer->CreateField(&field) != OGRERR_NONE)
      return GdalFailure(path, std::string("cannot create field ") + name + "." + spec.name);
  }
  return layer;
}

Status AddFeature(OGRLayer& layer, OGRFeature& feature, const std::string& path,
                  const std::string& what) {
  if (layer.CreateFeature(&feature) != OGRERR_NONE)
    return GdalFailure(path, "cannot write " + what);
  return Status::Ok();
}

// The plan-view box of the selected vertices.
Box VertexBox(const Tin& tin) {
  Box box;
  for (const TinVertex& v : tin.vertices) box.Add(Point2{v.x, v.y});
  return box;
}

Status WriteTriangles(GDALDataset& ds, const std::string& path, const OGRSpatialReference* srs,
                      const LoadedSurface& part) {
  TB_ASSIGN_OR_RETURN(OGRLayer * layer, CreateLayer(ds, path, "triangles", srs, wkbPolygon25D, "id",
                                                    {{"n0", OFTInteger64},
                                                     {"n1", OFTInteger64},
                                                     {"n2", OFTInteger64},
                                                     {"visible", OFTInteger, OFSTBoolean},
                                                     {"tag", OFTString}}));
  const Tin& tin = part.tin;
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    OGRFeature feature(layer->GetLayerDefn());
    feature.SetFID(part.triangle_ids[t]);
    for (int k = 0; k < 3; ++k) {
      if (tri.n[k] == kNoNeighbour) {
        feature.SetFieldNull(k);
      } else {
        feature.SetField(k, static_cast<GIntBig>(part.triangle_ids[tri.n[k]]));
      }
    }
    feature.SetField(3, tri.visible ? 1 : 0);
    if (tri.tag == kNoTag) {
      feature.SetFieldNull(4);
    } else {
      feature.SetField(4, tin.tags[static_cast<size_t>(tri.tag)].c_str());
    }
    auto ring = std::make_unique<OGRLinearRing>();
    for (int i = 0; i <= 3; ++i) {
      const TinVertex& p = tin.vertices[tri.v[i % 3]];
      ring->addPoint(p.x, p.y, p.z);
    }
    auto polygon = std::make_unique<OGRPolygon>();
    polygon->addRingDirectly(ring.release());
    feature.SetGeometryDirectly(polygon.release());
    TB_RETURN_IF_ERROR(
        AddFeature(*layer, feature, path, "triangle " + std::to_string(part.triangle_ids[t])));
  }
  return Status::Ok();
}

// The feature's polygons or lines as an OGR geometry (through the WKB the store keeps).
Result<std::unique_ptr<OGRGeometry>> FeatureGeometry(const EditorFeature& f) {
  const std::vector<uint8_t> wkb =
      f.lines.empty() ? PolygonsToWkb(f.polygons) : LinesToWkb(f.lines);
  OGRGeometry* geometry = nullptr;
  if (OGRGeometryFactory::createFromWkb(wkb.data(), nullptr, &geometry, wkb.size()) != OGRERR_NONE)
    return Status::Corruption(f.label + ": geometry does not convert to OGR");
  return std::unique_ptr<OGRGeometry>(geometry);
}

// The `features` and `breaklines` layers: with filter.feature only that feature, else every
// feature whose box meets `box`.
Status WriteFeatures(GDALDataset& ds, const std::string& path, const OGRSpatialReference* srs,
                     const std::vector<EditorFeature>& features, const Box& box,
                     int64_t only_feature, GpkgExportReport& report) {
  const std::vector<FieldSpec> fields = {{"mode", OFTString},
                                         {"tag", OFTString},
                                         {"level", OFTReal},
                                         {"attributes", OFTString, OFSTJSON}};
  TB_ASSIGN_OR_RETURN(OGRLayer * polygons,
                      CreateLayer(ds, path, "features", srs, wkbMultiPolygon, "id", fields));
  TB_ASSIGN_OR_RETURN(OGRLayer * lines,
                      CreateLayer(ds, path, "breaklines", srs, wkbMultiLineString, "id", fields));
  for (const EditorFeature& f : features) {
    if (only_feature != 0 ? f.id != only_feature : !BoxOf(f).Meets(box)) continue;
    if (f.mode == FeatureMode::kPoints) continue;  // its points are vertices
    const bool is_line = IsLineMode(f.mode);
    OGRLayer* layer = is_line ? lines : polygons;
    OGRFeature feature(layer->GetLayerDefn());
    feature.SetFID(f.id);
    feature.SetField(0, FeatureModeName(f.mode));
    if (f.tag) feature.SetField(1, f.tag->c_str());
    if (f.level) feature.SetField(2, *f.level);
    feature.SetField(3, f.attributes.dump().c_str());
    TB_ASSIGN_OR_RETURN(std::unique_ptr<OGRGeometry> geometry, FeatureGeometry(f));
    if (is_line) {
      geometry.reset(OGRGeometryFactory::forceToMultiLineString(geometry.release()));
    } else {
      geometry.reset(OGRGeometryFactory::forceToMultiPolygon(geometry.release()));
    }
    feature.SetGeometryDirectly(geometry.release());
    TB_RETURN_IF_ERROR(AddFeature(*layer, feature, path, f.label));
    ++(is_line ? report.breaklines : report.features);
  }
  return Status::Ok();
}

// The `constraints` layer: the constrained edges of the surface whose two vertices are selected,
// with their kind: 'soft' for a softline's, 'hard' for the others (db/edit/constraint_kinds.h).
Status WriteConstraints(GDALDataset& ds, const std::string& path, const OGRSpatialReference* srs,
                        Store& store, const SurfaceInfo& surface, const LoadedSurface& part,
                        const std::vector<EditorFeature>& features, GpkgExportReport& report) {
  TB_ASSIGN_OR_RETURN(OGRLayer * layer,
                      CreateLayer(ds, path, "constraints", srs, wkbLineString25D, "fid",
                                  {{"va", OFTInteger64},
                                   {"vb", OFTInteger64},
                                   {"feature", OFTInteger64},
                                   {"kind", OFTString}}));
  std::unordered_set<int64_t> softlines;
  for (const EditorFeature& f : features)
    if (f.mode == FeatureMode::kSoftline) softlines.insert(f.id);
  std::unordered_map<int64_t, uint32_t> index;
  index.reserve(part.vertex_ids.size());
  for (size_t i = 0; i < part.vertex_ids.size(); ++i)
    index.emplace(part.vertex_ids[i], static_cast<uint32_t>(i));
  MeshTables mesh(store.db(), surface);
  TB_ASSIGN_OR_RETURN(ConstraintCursor cursor, mesh.Constraints());
  ConstraintRow row;
  while (true) {
    TB_ASSIGN_OR_RETURN(bool more, cursor.Next(&row));
    if (!more) break;
    auto a = index.find(row.va);
    auto b = index.find(row.vb);
    if (a == index.end() || b == index.end()) continue;
    OGRFeature feature(layer->GetLayerDefn());
    feature.SetField(0, static_cast<GIntBig>(row.va));
    feature.SetField(1, static_cast<GIntBig>(row.vb));
    if (row.feature) feature.SetField(2, static_cast<GIntBig>(*row.feature));
    feature.SetField(3, row.feature && softlines.count(*row.feature) ? "soft" : "hard");
    auto line = std::make_unique<OGRLineString>();
    for (uint32_t v : {a->second, b->second}) {
      const TinVertex& p = part.tin.vertices[v];
      line->addPoint(p.x, p.y, p.z);
    }
    feature.SetGeometryDirectly(line.release());
    TB_RETURN_IF_ERROR(
        AddFeature(*layer, feature, path,
                   "constraint " + std::to_string(row.va) + "-" + std::to_string(row.vb)));
    ++report.constraints;
  }
  return Status::Ok();
}

// Writes every vector layer into a new GeoPackage at `file`, in one SQLite transaction; messages
// name `path`, the file the user asked for.
Status WriteVectors(const std::string& file, const std::string& path,
                    const OGRSpatialReference* srs, Store& store, const SurfaceInfo& surface,
                    const LoadedSurface& part, const std::vector<EditorFeature>& features,
                    const Box& box, int64_t only_feature, GpkgExportReport& report) {
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GPKG");
  if (driver == nullptr) return Status::IOError(path + ": GDAL has no GPKG driver");
  GdalDatasetPtr ds(driver->Create(file.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  if (!ds) return GdalFailure(path, "cannot create GeoPackage");
  if (ds->StartTransaction() != OGRERR_NONE) return GdalFailure(path, "cannot start writing");
  TB_RETURN_IF_ERROR(WriteTriangles(*ds, path, srs, part));
  TB_RETURN_IF_ERROR(WriteFeatures(*ds, path, srs, features, box, only_feature, report));
  TB_RETURN_IF_ERROR(WriteConstraints(*ds, path, srs, store, surface, part, features, report));
  if (ds->CommitTransaction() != OGRERR_NONE) return GdalFailure(path, "cannot commit layers");
  // GDAL 3.6's GDALClose returns nothing; a failed final write shows as the last error.
  CPLErrorReset();
  ds.reset();
  if (CPLGetLastErrorType() >= CE_Failure) return GdalFailure(path, "cannot finish GeoPackage");
  return Status::Ok();
}

// The DEM the raster comes from: options.dem, else the surface's own; nullopt for none.
Result<std::optional<DemInfo>> RasterDem(DemStore& dems, const SurfaceInfo& surface,
                                         const GpkgExportOptions& options) {
  if (!options.with_dem) return std::optional<DemInfo>();
  if (!options.dem.empty()) {
    TB_ASSIGN_OR_RETURN(DemInfo dem, dems.Find(options.dem));
    return std::optional<DemInfo>(std::move(dem));
  }
  if (!surface.dem) return std::optional<DemInfo>();
  TB_ASSIGN_OR_RETURN(DemInfo dem, dems.FindById(*surface.dem));
  return std::optional<DemInfo>(std::move(dem));
}

// Appends `grid` to the GeoPackage at `file` as the Float32 gridded coverage `dem`. The cells
// are written in place (nodata filled in) and lent to GDAL, so the window is in memory once.
Status AppendRaster(const std::string& file, const std::string& path, Grid& grid,
                    const DemInfo& dem) {
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* gpkg = GetGDALDriverManager()->GetDriverByName("GPKG");
  if (mem == nullptr || gpkg == nullptr) return Status::IOError(path + ": GDAL lacks MEM or GPKG");
  // Cells without data are NaN in the store; a file gets the DEM's declared nodata value where
  // there is one, since readers of gridded coverages key on `data_null` rather than on NaN.
  const bool declared = dem.nodata.has_value() && std::isfinite(*dem.nodata);
  const double nodata = declared ? *dem.nodata : std::numeric_limits<double>::quiet_NaN();
  if (declared) {
    for (float& c : grid.cells)
      if (std::isnan(c)) c = static_cast<float>(nodata);
  }
  const GridGeometry& g = grid.geometry;
  GdalDatasetPtr source(mem->Create("", static_cast<int>(g.width), static_cast<int>(g.height), 0,
                                    GDT_Float32, nullptr));
  if (!source) return GdalFailure(path, "cannot lend DEM " + dem.name + " to GDAL");
  const std::string pointer =
      "DATAPOINTER=" + std::to_string(reinterpret_cast<uintptr_t>(grid.cells.data()));
  const char* band_options[] = {pointer.c_str(), nullptr};
  if (source->AddBand(GDT_Float32, const_cast<char**>(band_options)) != CE_None)
    return GdalFailure(path, "cannot lend DEM " + dem.name + " to GDAL");
  double transform[6] = {g.origin_x, g.cell_x, 0, g.origin_y, 0, g.cell_y};
  source->SetGeoTransform(transform);
  if (!dem.crs_wkt.empty()) source->SetProjection(dem.crs_wkt.c_str());
  source->GetRasterBand(1)->SetNoDataValue(nodata);
  const char* options[] = {"APPEND_SUBDATASET=YES", "RASTER_TABLE=dem", "TILE_FORMAT=TIFF",
                           nullptr};
  GdalDatasetPtr out(gpkg->CreateCopy(file.c_str(), source.get(), FALSE,
                                      const_cast<char**>(options), nullptr, nullptr));
  if (!out) return GdalFailure(path, "cannot write DEM " + dem.name + " as a gridded coverage");
  CPLErrorReset();
  out.reset();
  if (CPLGetLastErrorType() >= CE_Failure) return GdalFailure(path, "cannot finish the raster");
  return Status::Ok();
}

}  // namespace

Result<GpkgExportReport> ExportGpkg(Store& store, const SurfaceInfo& surface,
                                    const GpkgExportOptions& options, const std::string& path) {
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  TB_ASSIGN_OR_RETURN(LoadedSurface part, SelectSurface(store, surface, options.filter));
  TB_ASSIGN_OR_RETURN(std::vector<EditorFeature> features, LoadFeatures(store, surface));
  TB_ASSIGN_OR_RETURN(std::optional<Crs> crs, store.GetCrs());
  DemStore dems(store);
  TB_ASSIGN_OR_RETURN(std::optional<DemInfo> dem, RasterDem(dems, surface, options));
  const Box box = VertexBox(part.tin);
  std::optional<Grid> grid;
  if (dem) {
    auto window = dems.ReadWindow(*dem, DemBox{box.min_x, box.min_y, box.max_x, box.max_y});
    if (!window.ok())
      return window.status().WithContext("the DEM under surface '" + surface.name + "'");
    grid = std::move(*window);
  }

  RegisterGdalDriversOnce();
  QuietGdalErrors quiet;
  TB_ASSIGN_OR_RETURN(OutputFile out, OutputFile::Create(path));
  std::unique_ptr<OGRSpatialReference> srs;
  if (crs) {
    srs = std::make_unique<OGRSpatialReference>(crs->ogr());
    srs->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  }
  GpkgExportReport report;
  report.triangles = static_cast<int64_t>(part.tin.triangles.size());
  report.vertices = static_cast<int64_t>(part.tin.vertices.size());
  TB_RETURN_IF_ERROR(WriteVectors(out.temp_path(), path, srs.get(), store, surface, part, features,
                                  box, options.filter.feature, report));
  if (grid) {
    TB_RETURN_IF_ERROR(AppendRaster(out.temp_path(), path, *grid, *dem));
    report.dem = dem->name;
    report.raster = grid->geometry;
  }
  TB_RETURN_IF_ERROR(out.Commit());
  return report;
}

}  // namespace tinbase
