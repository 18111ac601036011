// Polygon and line sources on the real files (Hamersley geology and faults, Luxembourg cantons)
// and on small bad inputs written here, each rejected with a message naming the place.
#include "core/vector/polygon_source.h"

#include <gdal_priv.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <fstream>
#include <memory>

#include "core/vector/gdal_session.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::DataPath;
using ::testing::HasSubstr;
using testing::TempDir;

Crs CrsOf(const std::string& text) {
  auto crs = Crs::FromUserInput(text);
  EXPECT_TRUE(crs.ok()) << text;
  return *crs;
}

GdalDatasetPtr OpenVector(const std::string& path) {
  RegisterGdalDriversOnce();
  return GdalDatasetPtr(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
}

// The open ring of `ring` without consecutive repeats (as the reader promises), optionally
// mapped through `ct`.
Ring OgrRing(const OGRLinearRing& ring, OGRCoordinateTransformation* ct = nullptr) {
  Ring out;
  for (int i = 0; i + 1 < ring.getNumPoints(); ++i) {
    double x = ring.getX(i), y = ring.getY(i);
    if (ct != nullptr) {
      EXPECT_TRUE(ct->Transform(1, &x, &y));
    }
    if (out.empty() || !SamePoint(out.back(), {x, y})) out.push_back({x, y});
  }
  return out;
}

// Same ring up to orientation (readers may reverse it), vertex by vertex within `tolerance`.
void ExpectSameRing(const Ring& got, const Ring& want, double tolerance) {
  ASSERT_EQ(got.size(), want.size());
  ASSERT_FALSE(want.empty());
  auto at = std::find_if(got.begin(), got.end(), [&](const Point2& p) {
    return std::abs(p.x - want[0].x) <= tolerance && std::abs(p.y - want[0].y) <= tolerance;
  });
  ASSERT_NE(at, got.end());
  const size_t start = at - got.begin();
  const size_t n = got.size();
  const bool forward = std::abs(got[(start + 1) % n].x - want[1].x) <= tolerance &&
                       std::abs(got[(start + 1) % n].y - want[1].y) <= tolerance;
  for (size_t i = 0; i < n; ++i) {
    const Point2& g = got[forward ? (start + i) % n : (start + n - i) % n];
    EXPECT_NEAR(g.x, want[i].x, tolerance) << "vertex " << i;
    EXPECT_NEAR(g.y, want[i].y, tolerance) << "vertex " << i;
  }
}

double Area(const Polygon& p) {
  double a = SignedDoubleArea(p.shell);
  for (const Ring& h : p.holes) a += SignedDoubleArea(h);  // holes are clockwise: negative
  return a / 2;
}

TEST(PolygonSource, ReadsHamersleyGeologyWithHolesAndAttributes) {
  const std::string path = DataPath("geology/hamersley/geology.geojson");
  VectorSourceOptions options;
  options.tag_field = "unitname";
  auto features = ReadPolygonFeatures(path, options);
  ASSERT_TRUE(features.ok()) << features.status().ToString();
  ASSERT_EQ(features->size(), 61u);
  size_t holes = 0;
  for (const PolygonFeature& f : *features) {
    ASSERT_EQ(f.polygons.size(), 1u) << f.label;
    holes += f.polygons[0].holes.size();
    EXPECT_GT(SignedDoubleArea(f.polygons[0].shell), 0) << f.label;
    for (const Ring& h : f.polygons[0].holes) EXPECT_LT(SignedDoubleArea(h), 0) << f.label;
    ASSERT_TRUE(f.attributes.contains("unitname")) << f.label;
    ASSERT_TRUE(f.attributes["unitname"].is_string()) << f.label;
    EXPECT_EQ(f.tag.value_or("?"), f.attributes["unitname"].get<std::string>());
    EXPECT_THAT(f.label, HasSubstr("geology.geojson feature "));
  }
  EXPECT_EQ(holes, 3u);

  // Rings and areas agree with OGR's own reading of the file.
  auto ds = OpenVector(path);
  ASSERT_TRUE(ds);
  OGRLayer* layer = ds->GetLayer(0);
  size_t i = 0;
  for (auto& feature : *layer) {
    const PolygonFeature& f = (*features)[i++];
    EXPECT_EQ(f.fid, feature->GetFID());
    EXPECT_EQ(f.attributes["unitname"], feature->GetFieldAsString("unitname"));
    const OGRMultiPolygon* mp = feature->GetGeometryRef()->toMultiPolygon();
    const OGRPolygon* polygon = mp->getGeometryRef(0);
    ExpectSameRing(f.polygons[0].shell, OgrRing(*polygon->getExteriorRing()), 0);
    ASSERT_EQ(f.polygons[0].holes.size(), static_cast<size_t>(polygon->getNumInteriorRings()));
    for (int h = 0; h < polygon->getNumInteriorRings(); ++h)
      ExpectSameRing(f.polygons[0].holes[h], OgrRing(*polygon->getInteriorRing(h)), 0);
    EXPECT_NEAR(Area(f.polygons[0]), mp->get_Area(), 1e-6 * mp->get_Area()) << f.label;
  }
}

TEST(PolygonSource, ReprojectsLuxembourgCantonsToUtm31) {
  const std::string path = DataPath("vector/lux/lux.shp");
  VectorSourceOptions options;
  options.target_crs = CrsOf("EPSG:32631");
  auto features = ReadPolygonFeatures(path, options);
  ASSERT_TRUE(features.ok()) << features.status().ToString();
  ASSERT_EQ(features->size(), 12u);

  // The reference: OGR's own transformation of the file's coordinates.
  auto ds = OpenVector(path);
  ASSERT_TRUE(ds);
  OGRLayer* layer = ds->GetLayer(0);
  OGRSpatialReference source(*layer->GetSpatialRef());
  source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> ct(
      OGRCreateCoordinateTransformation(&source, &options.target_crs->ogr()));
  ASSERT_TRUE(ct);
  std::unique_ptr<OGRFeature> first(layer->GetFeature(3));
  ASSERT_TRUE(first);
  const OGRPolygon* polygon = first->GetGeometryRef()->toPolygon();
  const Ring want = OgrRing(*polygon->getExteriorRing(), ct.get());
  const PolygonFeature& got = (*features)[3];
  EXPECT_EQ(got.fid, 3);
  EXPECT_EQ(got.attributes["NAME_2"], first->GetFieldAsString("NAME_2"));
  EXPECT_TRUE(got.attributes["POP"].is_number_integer());
  ExpectSameRing(got.polygons[0].shell, want, 1e-6);
  // Plausible UTM 31N metres for Luxembourg, not degrees.
  EXPECT_GT(got.polygons[0].shell[0].x, 600000);
  EXPECT_GT(got.polygons[0].shell[0].y, 5400000);

  // The attribute filter selects; the districts partition the cantons.
  size_t total = 0;
  for (const char* district : {"Diekirch", "Grevenmacher", "Luxembourg"}) {
    VectorSourceOptions filtered;
    filtered.where = std::string("NAME_1 = '") + district + "'";
    filtered.tag_field = "NAME_1";
    auto part = ReadPolygonFeatures(path, filtered);
    ASSERT_TRUE(part.ok()) << part.status().ToString();
    EXPECT_GT(part->size(), 0u);
    EXPECT_LT(part->size(), 12u);
    for (const PolygonFeature& f : *part) EXPECT_EQ(f.tag.value_or(""), district);
    total += part->size();
  }
  EXPECT_EQ(total, 12u);
}

TEST(PolygonSource, ReadsFaultsAsLines) {
  const std::string path = DataPath("geology/hamersley/faults.geojson");
  auto lines = ReadLineFeatures(path, {});
  ASSERT_TRUE(lines.ok()) << lines.status().ToString();
  ASSERT_EQ(lines->size(), 35u);
  auto ds = OpenVector(path);
  size_t i = 0;
  for (auto& feature : *ds->GetLayer(0)) {
    const LineFeature& f = (*lines)[i++];
    const OGRMultiLineString* ml = feature->GetGeometryRef()->toMultiLineString();
    ASSERT_EQ(f.lines.size(), static_cast<size_t>(ml->getNumGeometries())) << f.label;
    for (size_t k = 0; k < f.lines.size(); ++k) {
      const OGRLineString* ls = ml->getGeometryRef(static_cast<int>(k));
      ASSERT_GE(f.lines[k].size(), 2u);
      EXPECT_LE(f.lines[k].size(), static_cast<size_t>(ls->getNumPoints()));
      const int last = ls->getNumPoints() - 1;
      EXPECT_TRUE(SamePoint(f.lines[k].front(), {ls->getX(0), ls->getY(0)})) << f.label;
      EXPECT_TRUE(SamePoint(f.lines[k].back(), {ls->getX(last), ls->getY(last)})) << f.label;
    }
    EXPECT_TRUE(f.attributes.contains("fname")) << f.label;
  }
  // Each reader refuses the other's geometry, naming the feature.
  auto as_polygons = ReadPolygonFeatures(path, {});
  ASSERT_FALSE(as_polygons.ok());
  EXPECT_THAT(as_polygons.status().message(),
              HasSubstr("faults.geojson feature 0: geometry is a Multi Line String, not a "
                        "Polygon or MultiPolygon"));
  auto as_lines = ReadLineFeatures(DataPath("geology/hamersley/geology.geojson"), {});
  ASSERT_FALSE(as_lines.ok());
  EXPECT_THAT(as_lines.status().message(), HasSubstr("geology.geojson feature 0: geometry is a "
                                                     "Multi Polygon, not a LineString"));
}

TEST(PolygonSource, ReadsGeoPackageLayersAndKml) {
  TempDir dir;
  auto source = OpenVector(DataPath("vector/lux/lux.shp"));
  ASSERT_TRUE(source);
  const std::string gpkg = dir.Path("two.gpkg");
  const std::string kml = dir.Path("lux.kml");
  {
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GPKG");
    GdalDatasetPtr out(driver->Create(gpkg.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    ASSERT_TRUE(out);
    ASSERT_NE(out->CopyLayer(source->GetLayer(0), "cantons"), nullptr);
    ASSERT_NE(out->CopyLayer(source->GetLayer(0), "cantons_copy"), nullptr);
    GDALDriver* kml_driver = GetGDALDriverManager()->GetDriverByName("KML");
    GdalDatasetPtr kml_out(kml_driver->Create(kml.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    ASSERT_TRUE(kml_out);
    ASSERT_NE(kml_out->CopyLayer(source->GetLayer(0), "cantons"), nullptr);
  }
  VectorSourceOptions options;
  options.target_crs = CrsOf("EPSG:32631");
  auto ambiguous = ReadPolygonFeatures(gpkg, options);
  ASSERT_FALSE(ambiguous.ok());
  EXPECT_EQ(ambiguous.status().message(),
            "two.gpkg: source has 2 layers (cantons, cantons_copy); name one");
  options.layer = "nope";
  auto unknown = ReadPolygonFeatures(gpkg, options);
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.status().message(),
            "two.gpkg: no layer named 'nope' (layers: cantons, cantons_copy)");

  options.layer = "cantons_copy";
  auto from_gpkg = ReadPolygonFeatures(gpkg, options);
  ASSERT_TRUE(from_gpkg.ok()) << from_gpkg.status().ToString();
  options.layer.clear();
  auto from_shp = ReadPolygonFeatures(DataPath("vector/lux/lux.shp"), options);
  ASSERT_TRUE(from_shp.ok());
  auto from_kml = ReadPolygonFeatures(kml, options);
  ASSERT_TRUE(from_kml.ok()) << from_kml.status().ToString();
  ASSERT_EQ(from_gpkg->size(), from_shp->size());
  ASSERT_EQ(from_kml->size(), from_shp->size());
  for (size_t i = 0; i < from_shp->size(); ++i) {
    ExpectSameRing((*from_gpkg)[i].polygons[0].shell, (*from_shp)[i].polygons[0].shell, 1e-9);
    // KML stores text with fewer digits: equal to well under a millimetre.
    ExpectSameRing((*from_kml)[i].polygons[0].shell, (*from_shp)[i].polygons[0].shell, 1e-3);
  }
}

// A one-feature GeoJSON FeatureCollection with `geometry` (JSON text) and properties.
std::string WriteGeoJson(const TempDir& dir, const std::string& name, const std::string& geometry,
                         const std::string& extra = "") {
  const std::string path = dir.Path(name);
  std::ofstream(path) << R"({"type": "FeatureCollection", "features": [{"type": "Feature", )"
                      << extra << R"("properties": {"kind": "test"}, "geometry": )" << geometry
                      << "}]}";
  return path;
}

Status PolygonError(const std::string& path, const VectorSourceOptions& options = {}) {
  auto result = ReadPolygonFeatures(path, options);
  EXPECT_FALSE(result.ok()) << path;
  return result.ok() ? Status::Ok() : result.status();
}

TEST(PolygonSource, RejectsBadRingsNamingFeatureRingAndVertex) {
  TempDir dir;
  struct Case {
    const char* name;
    const char* geometry;
    const char* message;
  };
  const Case cases[] = {
      {"open.geojson", R"({"type": "Polygon", "coordinates": [[[0,0],[4,0],[4,4],[0,4]]]})",
       "open.geojson feature 0, ring 0: ring is not closed (vertex 0 (0, 0), last vertex 3 "
       "(0, 4))"},
      {"few.geojson", R"({"type": "Polygon", "coordinates": [[[0,0],[1,1],[1,1],[0,0]]]})",
       "few.geojson feature 0, ring 0: fewer than 3 distinct points (2)"},
      {"nan.geojson", R"({"type": "Polygon", "coordinates": [[[0,0],[4,0],[4,NaN],[0,4],[0,0]]]})",
       "nan.geojson feature 0, ring 0, vertex 2: coordinate is not finite (4, nan)"},
      {"bowtie.geojson", R"({"type": "Polygon", "coordinates": [[[0,0],[2,2],[2,0],[0,2],[0,0]]]})",
       "bowtie.geojson feature 0, ring 0, vertex 0: ring crosses itself at (1, 1) (edges 0-1 and "
       "2-3)"},
      {"touch.geojson",
       R"({"type": "Polygon", "coordinates": [[[0,0],[4,0],[2,2],[4,4],[0,4],[2,2],[0,0]]]})",
       "touch.geojson feature 0, ring 0, vertex 1: ring touches itself at (2, 2) (edges 1-2 and "
       "4-5)"},
      {"fold.geojson",
       R"({"type": "Polygon", "coordinates": [[[0,0],[4,0],[4,4],[4,2],[0,4],[0,0]]]})",
       "fold.geojson feature 0, ring 0, vertex 2: ring folds back on itself at (4, 4)"},
      {"outside.geojson",
       R"({"type": "Polygon", "coordinates": [[[0,0],[10,0],[10,10],[0,10],[0,0]],
           [[20,20],[22,20],[22,22],[20,20]]]})",
       "outside.geojson feature 0, ring 1, vertex 0: hole lies outside its shell (ring 0) at "
       "(20, 20)"},
      {"crossing.geojson",
       R"({"type": "Polygon", "coordinates": [[[0,0],[10,0],[10,10],[0,10],[0,0]],
           [[5,5],[15,5],[15,6],[5,5]]]})",
       "crossing.geojson feature 0, ring 0, vertex 1: crosses ring 1 at (10, 5) (edges 1-2 and "
       "ring 1 0-1)"},
      {"nested.geojson",
       R"({"type": "Polygon", "coordinates": [[[0,0],[10,0],[10,10],[0,10],[0,0]],
           [[1,1],[1,9],[9,9],[9,1],[1,1]], [[2,2],[2,3],[3,3],[2,2]]]})",
       "nested.geojson feature 0, ring 2, vertex 0: hole lies inside hole 1 at (2, 2)"},
      {"multi.geojson",
       R"({"type": "MultiPolygon", "coordinates": [[[[0,0],[1,0],[1,1],[0,0]]],
           [[[5,5],[7,7],[7,5],[5,7],[5,5]]]]})",
       "multi.geojson feature 0, polygon 1, ring 0, vertex 0: ring crosses itself at (6, 6) "
       "(edges 0-1 and 2-3)"},
      {"point.geojson", R"({"type": "Point", "coordinates": [1, 2]})",
       "point.geojson feature 0: geometry is a Point, not a Polygon or MultiPolygon"},
      {"null.geojson", "null", "null.geojson feature 0: feature has no geometry"},
  };
  for (const Case& c : cases) {
    const Status status = PolygonError(WriteGeoJson(dir, c.name, c.geometry));
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << c.name;
    EXPECT_EQ(status.message(), c.message) << c.name;
  }
}

TEST(PolygonSource, FeatureIdsComeFromTheFile) {
  TempDir dir;
  const std::string path = WriteGeoJson(
      dir, "id.geojson", R"({"type": "Polygon", "coordinates": [[[0,0],[2,2],[2,0],[0,2],[0,0]]]})",
      R"("id": 17, )");
  EXPECT_THAT(PolygonError(path).message(), HasSubstr("id.geojson feature 17, ring 0, vertex 0"));
}

TEST(PolygonSource, RejectsBadSourcesNamingThem) {
  TempDir dir;
  const std::string square = R"({"type": "Polygon", "coordinates": [[[0,0],[4,0],[4,4],[0,0]]]})";
  const std::string good = WriteGeoJson(dir, "good.geojson", square);
  ASSERT_TRUE(ReadPolygonFeatures(good, {}).ok());

  const std::string empty = dir.Path("empty.geojson");
  std::ofstream(empty) << R"({"type": "FeatureCollection", "features": []})";
  EXPECT_THAT(PolygonError(empty).message(), HasSubstr("empty.geojson: no features in layer"));

  VectorSourceOptions field;
  field.tag_field = "formation";
  EXPECT_EQ(PolygonError(good, field).message(),
            "good.geojson: layer 'good' has no field named 'formation' (fields: kind)");

  VectorSourceOptions filter;
  filter.where = "kind = 'other'";
  EXPECT_EQ(PolygonError(good, filter).message(),
            "good.geojson: no features in layer 'good' match filter 'kind = 'other''");
  filter.where = "kind ===";
  EXPECT_THAT(PolygonError(good, filter).message(),
              HasSubstr("good.geojson: bad attribute filter 'kind ==='"));

  auto missing = ReadPolygonFeatures(dir.Path("missing.geojson"), {});
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.status().code(), StatusCode::kNotFound);
  EXPECT_THAT(missing.status().message(), HasSubstr("missing.geojson"));

  const std::string text = dir.Path("notes.txt");
  std::ofstream(text) << "no geometry here\n";
  EXPECT_THAT(PolygonError(text).message(), HasSubstr("notes.txt: not a vector source"));

  // Latitude 95 has no place in UTM.
  const std::string far = WriteGeoJson(
      dir, "far.geojson", R"({"type": "Polygon", "coordinates": [[[0,0],[4,0],[4,95],[0,0]]]})");
  VectorSourceOptions utm;
  utm.target_crs = CrsOf("EPSG:32631");
  EXPECT_THAT(PolygonError(far, utm).message(),
              HasSubstr("far.geojson feature 0, ring 0, vertex 2: (4, 95) cannot be reprojected "
                        "from EPSG:4326 to EPSG:32631"));
}

TEST(PolygonSource, SourceWithoutCrsNeedsOneToBeReprojected) {
  TempDir dir;
  const std::string path = dir.Path("bare.shp");
  {
    RegisterGdalDriversOnce();
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("ESRI Shapefile");
    GdalDatasetPtr ds(driver->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    ASSERT_TRUE(ds);
    OGRLayer* layer = ds->CreateLayer("bare", nullptr, wkbPolygon, nullptr);
    ASSERT_NE(layer, nullptr);
    OGRFeature feature(layer->GetLayerDefn());
    OGRGeometry* g = nullptr;
    ASSERT_EQ(OGRGeometryFactory::createFromWkt("POLYGON ((6 49.5,6.1 49.5,6.1 49.6,6 49.5))",
                                                nullptr, &g),
              OGRERR_NONE);
    feature.SetGeometryDirectly(g);
    ASSERT_EQ(layer->CreateFeature(&feature), OGRERR_NONE);
  }
  VectorSourceOptions options;
  EXPECT_TRUE(ReadPolygonFeatures(path, options).ok());  // no target: taken as it is
  options.target_crs = CrsOf("EPSG:32631");
  EXPECT_EQ(PolygonError(path, options).message(),
            "bare.shp: source has no CRS, so it cannot be reprojected to EPSG:32631 (name the "
            "source's CRS)");
  options.assumed_source_crs = CrsOf("EPSG:4326");
  auto features = ReadPolygonFeatures(path, options);
  ASSERT_TRUE(features.ok()) << features.status().ToString();
  EXPECT_GT((*features)[0].polygons[0].shell[0].x, 100000);  // now in metres
}

TEST(LineSource, RejectsDegenerateAndNonFiniteLines) {
  TempDir dir;
  auto one = ReadLineFeatures(
      WriteGeoJson(dir, "one.geojson", R"({"type": "LineString", "coordinates": [[1,1],[1,1]]})"),
      {});
  ASSERT_FALSE(one.ok());
  EXPECT_EQ(one.status().message(), "one.geojson feature 0, line 0: fewer than 2 distinct points");
  auto nan = ReadLineFeatures(
      WriteGeoJson(
          dir, "nan.geojson",
          R"({"type": "MultiLineString", "coordinates": [[[0,0],[1,1]],[[2,2],[Infinity,3]]]})"),
      {});
  ASSERT_FALSE(nan.ok());
  EXPECT_EQ(nan.status().message(),
            "nan.geojson feature 0, line 1, vertex 1: coordinate is not finite (inf, 3)");
}

}  // namespace
}  // namespace tinbase
