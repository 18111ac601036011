// The store read as a GeoPackage with no export (migration 0010, docs/format.md "The store as a
// GeoPackage"): GDAL's ogrinfo lists its layers with the store's counts, rows, CRS and exact
// coordinates, and the layers follow every write with nothing done to keep them in step.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

#include "db/feature_store.h"
#include "db/store.h"
#include "db/surface_store.h"
#include "tests/support/gdal_tools.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::HaveTool;
using testing::RunTool;
using testing::TempDir;
using testing::ValueAfter;

std::string Q(const std::string& s) { return "'" + s + "'"; }

// Three vertices with zeros, negative values, a tiny and a huge one: the bytes the views build
// must be exactly the stored doubles whatever the exponent and sign.
Tin AwkwardTin() {
  Tin tin;
  tin.vertices = {{0.0, -1.5, 0.0, VertexKind::kUser},
                  {-0.001953125, -7.25e6, -1234.5678901234567, VertexKind::kUser},
                  {1e-300, 3.0000000000000004, 1e300, VertexKind::kUser}};
  TinTriangle t;
  t.v = {0, 2, 1};  // counter-clockwise
  tin.triangles = {t};
  return tin;
}

class StoreGeoPackageTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(HaveTool("ogrinfo"));
    path_ = dir_.Path("s.tinbase");
    auto store = Store::Create(path_, "EPSG:32632");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    testing::RandomTinOptions options;
    options.points = 300;
    options.ring = true;
    Tin tin = testing::RandomDelaunayTin(options);
    for (size_t t = 0; t < tin.triangles.size(); t += 5) tin.triangles[t].visible = false;
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    SurfaceInfo spec;
    spec.name = "terrain";
    spec.method = "test";
    auto info = SurfaceStore(*store_).Create(spec, tin);
    ASSERT_TRUE(info.ok()) << info.status().ToString();
    surface_ = *info;
    spec.name = "awkward";
    ASSERT_TRUE(SurfaceStore(*store_).Create(spec, AwkwardTin()).ok());
    EditorFeature unit;
    unit.mode = FeatureMode::kFill;
    unit.tag = "basalt";
    unit.polygons = {Polygon{{{604500, 5104500}, {605500, 5104500}, {605500, 5105500}}, {}}};
    ASSERT_TRUE(WriteFeature(*store_, surface_, 1, unit).ok());
    unit_ = unit.id;
    EditorFeature fault;
    fault.mode = FeatureMode::kBreakline;
    fault.lines = {{{601000, 5101000}, {604000, 5104000}}};
    ASSERT_TRUE(WriteFeature(*store_, surface_, 1, fault).ok());
    ASSERT_TRUE((*tx)->Commit().ok());
  }

  // GDAL's GeoPackage driver on the store: the "GPKG:" prefix picks it without the warning a
  // .tinbase name gets (WhichDriverAFileNameGets).
  std::string Gpkg() const { return Q("GPKG:" + path_); }

  int64_t Count(const std::string& layer) const {
    auto r = RunTool("ogrinfo -ro -so " + Gpkg() + " " + layer);
    EXPECT_EQ(r.exit_code, 0) << r.out;
    const std::string value = ValueAfter(r.out, "Feature Count: ");
    return value.empty() ? -1 : std::stoll(value);
  }

  TempDir dir_;
  std::string path_;
  std::unique_ptr<Store> store_;
  SurfaceInfo surface_;
  int64_t unit_ = 0;
};

TEST_F(StoreGeoPackageTest, OgrinfoListsTheLayersAndNothingElse) {
  auto r = RunTool("ogrinfo -ro " + Gpkg());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("using driver `GPKG' successful"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("Warning"), std::string::npos) << r.out;
  const std::string expected =
      "1: tinbase_triangles (3D Polygon)\n"
      "2: tinbase_vertices (3D Point)\n"
      "3: tinbase_constraints (3D Line String)\n"
      "4: tinbase_features (Multi Polygon)\n"
      "5: tinbase_breaklines (Multi Line String)\n"
      "6: surfaces (None)\n";
  EXPECT_EQ(r.out.substr(r.out.find("1: ")), expected);
}

TEST_F(StoreGeoPackageTest, CountsRowsAndCrsAreTheStores) {
  SurfaceStore surfaces(*store_);
  auto counts = surfaces.Count(surface_);
  ASSERT_TRUE(counts.ok());
  EXPECT_EQ(Count("tinbase_triangles"), counts->triangles + 1);
  EXPECT_EQ(Count("tinbase_vertices"), counts->vertices + 3);
  EXPECT_EQ(Count("tinbase_constraints"), counts->constraints);
  EXPECT_EQ(Count("tinbase_features"), 1);
  EXPECT_EQ(Count("tinbase_breaklines"), 1);
  EXPECT_EQ(Count("surfaces"), 2);

  auto summary = RunTool("ogrinfo -ro -so " + Gpkg() + " tinbase_triangles");
  EXPECT_NE(summary.out.find("ID[\"EPSG\",32632]"), std::string::npos) << summary.out;
  EXPECT_EQ(ValueAfter(summary.out, "FID Column = "), "fid");
  EXPECT_EQ(ValueAfter(summary.out, "Geometry Column = "), "geom");
  EXPECT_EQ(summary.out.find("geom: "), std::string::npos) << "geom is not an attribute";

  auto all = surfaces.Load(surface_);
  ASSERT_TRUE(all.ok());
  for (size_t t : {size_t{0}, all->triangle_ids.size() / 2, size_t{5}}) {
    const int64_t id = all->triangle_ids[t];
    auto row = surfaces.Triangle(surface_, id);
    ASSERT_TRUE(row.ok());
    auto dump = RunTool("ogrinfo -ro " + Gpkg() + " tinbase_triangles -fid " + std::to_string(id));
    ASSERT_NE(dump.out.find("OGRFeature(tinbase_triangles):" + std::to_string(id)),
              std::string::npos)
        << dump.out;
    EXPECT_EQ(ValueAfter(dump.out, "surface (String) = "), "terrain");
    const char* names[3][2] = {{"v0 (Integer64) = ", "n0 (Integer64) = "},
                               {"v1 (Integer64) = ", "n1 (Integer64) = "},
                               {"v2 (Integer64) = ", "n2 (Integer64) = "}};
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(ValueAfter(dump.out, names[k][0]), std::to_string(row->v[k]));
      EXPECT_EQ(ValueAfter(dump.out, names[k][1]),
                row->n[k] ? std::to_string(*row->n[k]) : "(null)");
    }
    EXPECT_EQ(ValueAfter(dump.out, "visible (Integer64) = "), row->visible ? "1" : "0");
    EXPECT_EQ(ValueAfter(dump.out, "tag (String) = "),
              row->tag ? *surfaces.TagValue(surface_, *row->tag) : "(null)");
    auto v0 = surfaces.Vertex(surface_, row->v[0]);
    char corner[128];
    std::snprintf(corner, sizeof(corner), "POLYGON Z ((%.15g %.15g %.15g,", v0->x, v0->y, v0->z);
    EXPECT_NE(dump.out.find(corner), std::string::npos) << corner << "\n" << dump.out;
  }
  auto unit = RunTool("ogrinfo -ro " + Gpkg() + " tinbase_features -fid " + std::to_string(unit_));
  EXPECT_EQ(ValueAfter(unit.out, "mode (String) = "), "fill");
  EXPECT_EQ(ValueAfter(unit.out, "tag (String) = "), "basalt");
  EXPECT_NE(unit.out.find("MULTIPOLYGON (((604500 5104500,605500 5104500,605500 5105500,604500 "
                          "5104500)))"),
            std::string::npos)
      << unit.out;
}

// The views' bytes are the stored doubles bit for bit (checked here through SQLite itself, and
// for the awkward triangle through ogrinfo's 17-digit output of the same blob).
TEST_F(StoreGeoPackageTest, CoordinatesAreTheStoredDoublesBitForBit) {
  auto stmt = store_->db().Prepare(
      "SELECT v.x, v.y, v.z, CAST(c.xyz AS BLOB) FROM vertices v "
      "JOIN tinbase_gpkg_vertex_xyz c ON c.id = v.id");
  ASSERT_TRUE(stmt.ok()) << stmt.status().ToString();
  int64_t rows = 0;
  while (*(*stmt)->Step()) {
    double xyz[3] = {(*stmt)->ColumnDouble(0), (*stmt)->ColumnDouble(1), (*stmt)->ColumnDouble(2)};
    size_t size = 0;
    const uint8_t* blob = (*stmt)->ColumnBlob(3, &size);
    ASSERT_EQ(size, sizeof(xyz));
    EXPECT_EQ(std::memcmp(blob, xyz, sizeof(xyz)), 0)
        << "vertex (" << xyz[0] << ", " << xyz[1] << ", " << xyz[2] << ")";
    ++rows;
  }
  EXPECT_GT(rows, 300);
  auto awkward = RunTool("ogrinfo -ro " + Gpkg() +
                         " -sql \"SELECT geom FROM tinbase_vertices WHERE surface = 'awkward'\"" +
                         " --config OGR_WKT_PRECISION 17");
  EXPECT_NE(awkward.out.find("POINT Z (-0.001953125 -7250000 -1234.5678901234567)"),
            std::string::npos)
      << awkward.out;
}

TEST_F(StoreGeoPackageTest, LayersFollowEveryWrite) {
  const int64_t features = Count("tinbase_features");
  {
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    EditorFeature more;
    more.mode = FeatureMode::kErase;
    more.polygons = {Polygon{{{606000, 5106000}, {607000, 5106000}, {607000, 5107000}}, {}}};
    ASSERT_TRUE(WriteFeature(*store_, surface_, 2, more).ok());
    ASSERT_TRUE(DeleteFeature(*store_, unit_).ok());
    SurfaceInfo spec;
    spec.name = "second";
    spec.method = "test";
    ASSERT_TRUE(SurfaceStore(*store_).Create(spec, AwkwardTin()).ok());
    ASSERT_TRUE((*tx)->Commit().ok());
  }
  EXPECT_EQ(Count("tinbase_features"), features);
  EXPECT_EQ(Count("surfaces"), 3);
  auto second = RunTool("ogrinfo -ro " + Gpkg() +
                        " -sql \"SELECT count(*) AS n FROM tinbase_triangles WHERE surface = "
                        "'second'\"");
  EXPECT_NE(second.out.find("n (Integer) = 1"), std::string::npos) << second.out;
  testing::ExpectStoreIntact(*store_);
}

// Before a CRS is set the layers are in GeoPackage's "undefined cartesian" system (-1).
TEST_F(StoreGeoPackageTest, AStoreWithoutCrsIsUndefinedCartesian) {
  const std::string bare = dir_.Path("bare.tinbase");
  {
    auto store = Store::Create(bare, "");
    ASSERT_TRUE(store.ok());
    auto tx = (*store)->BeginWrite();
    ASSERT_TRUE(tx.ok());
    SurfaceInfo spec;
    spec.name = "s";
    spec.method = "test";
    ASSERT_TRUE(SurfaceStore(**store).Create(spec, AwkwardTin()).ok());
    ASSERT_TRUE((*tx)->Commit().ok());
  }
  auto r = RunTool("ogrinfo -ro -so " + Q("GPKG:" + bare) + " tinbase_triangles");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_EQ(ValueAfter(r.out, "Feature Count: "), "1");
  EXPECT_NE(r.out.find("ENGCRS[\"Undefined Cartesian SRS\""), std::string::npos) << r.out;
}

// What a reader that picks drivers by file name sees (migration 0013): the store opens as a
// GeoPackage under its own name, with GDAL's warning about the extension, and under a *.gpkg
// name with no warning; either way with the layers, their geometry and counts.
TEST_F(StoreGeoPackageTest, WhichDriverAFileNameGets) {
  const std::string named = dir_.Path("copy.gpkg");
  const int64_t triangles = Count("tinbase_triangles");
  store_.reset();
  std::filesystem::copy_file(path_, named);
  auto gpkg = RunTool("ogrinfo -ro -so " + Q(named) + " tinbase_triangles");
  ASSERT_EQ(gpkg.exit_code, 0) << gpkg.out;
  EXPECT_NE(gpkg.out.find("using driver `GPKG'"), std::string::npos) << gpkg.out;
  EXPECT_EQ(gpkg.out.find("Warning"), std::string::npos) << gpkg.out;
  EXPECT_NE(gpkg.out.find("Geometry: 3D Polygon"), std::string::npos) << gpkg.out;
  EXPECT_EQ(ValueAfter(gpkg.out, "Feature Count: "), std::to_string(triangles));
  auto own = RunTool("ogrinfo -ro " + Q(path_));
  ASSERT_EQ(own.exit_code, 0) << own.out;
  EXPECT_NE(own.out.find("using driver `GPKG'"), std::string::npos) << own.out;
  EXPECT_NE(own.out.find("non conformant file extension"), std::string::npos) << own.out;
  EXPECT_NE(own.out.find("tinbase_triangles (3D Polygon)"), std::string::npos) << own.out;
  auto plain = RunTool("ogrinfo -ro -so " + Q(path_) + " tinbase_triangles");
  EXPECT_EQ(ValueAfter(plain.out, "Feature Count: "), std::to_string(triangles));
  EXPECT_NE(plain.out.find("Geometry: 3D Polygon"), std::string::npos) << plain.out;
}

}  // namespace
}  // namespace tinbase
