// ExportTin writes OBJ and GeoJSON that read back (by a plain parser and by OGR) to the same
// surface: counts, coordinates, counter-clockwise order, visibility, tags and CRS.
#include "core/export/tin_export.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>

#include "tests/support/grid_tin.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

// A 12 x 9 grid in UTM 32N with irrational-looking coordinates (so shortest round-trip printing
// matters), a band of invisible triangles and two tags.
Tin SampleTin() {
  Tin tin = testing::MakeGridTin(
      12, 9, 30.123456789012345, 612345.678901234, 5171234.56789012, [](double x, double y) {
        return 1000.0 + std::sin(x / 77.7) * 123.456789 + std::cos(y / 51.3) / 3.0;
      });
  tin.tags = {"granite", "schist"};
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    if (t % 7 == 3 || (t >= 40 && t < 70)) tin.triangles[t].visible = false;
    if (t % 5 == 0) tin.triangles[t].tag = static_cast<int32_t>((t / 5) % 2);
  }
  return tin;
}

double Cross(const TinVertex& a, const TinVertex& b, const TinVertex& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

struct ObjFile {
  std::vector<TinVertex> vertices;
  std::vector<std::array<int64_t, 3>> faces;  // 1-based as written
  std::vector<std::string> comments;
};

ObjFile ParseObj(const std::string& path) {
  ObjFile obj;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "v") {
      TinVertex v;
      ls >> v.x >> v.y >> v.z;
      EXPECT_FALSE(ls.fail()) << line;
      obj.vertices.push_back(v);
    } else if (word == "f") {
      std::array<int64_t, 3> f{};
      ls >> f[0] >> f[1] >> f[2];
      EXPECT_FALSE(ls.fail()) << line;
      obj.faces.push_back(f);
    } else if (word == "#") {
      obj.comments.push_back(line);
    } else {
      ADD_FAILURE() << "unexpected OBJ line: " << line;
    }
  }
  return obj;
}

void ExpectSameVertex(const TinVertex& got, const TinVertex& want) {
  EXPECT_NEAR(got.x, want.x, 1e-9);
  EXPECT_NEAR(got.y, want.y, 1e-9);
  EXPECT_NEAR(got.z, want.z, 1e-9);
}

// The vertices the visible triangles use, counted independently of the exporter.
size_t VisibleVertexCount(const Tin& tin) {
  std::set<uint32_t> used;
  for (const TinTriangle& t : tin.triangles)
    if (t.visible) used.insert(t.v.begin(), t.v.end());
  return used.size();
}

size_t VisibleTriangleCount(const Tin& tin) {
  size_t n = 0;
  for (const TinTriangle& t : tin.triangles) n += t.visible ? 1 : 0;
  return n;
}

TEST(ParseExportFormat, KnowsObjAndGeoJson) {
  EXPECT_EQ(*ParseExportFormat("obj"), ExportFormat::kObj);
  EXPECT_EQ(*ParseExportFormat("geojson"), ExportFormat::kGeoJson);
  auto bad = ParseExportFormat("dxf");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("'dxf'"), std::string::npos);
}

TEST(ExportObj, RoundTripsEveryVertexAndFaceExactly) {
  const Tin tin = SampleTin();
  auto crs = Crs::FromUserInput("EPSG:32632");
  ASSERT_TRUE(crs.ok());
  TempDir dir;
  const std::string path = dir.Path("s.obj");
  auto report = ExportTin(tin, &*crs, path, {});
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->vertices, static_cast<int64_t>(tin.vertices.size()));
  EXPECT_EQ(report->triangles, static_cast<int64_t>(tin.triangles.size()));

  const ObjFile obj = ParseObj(path);
  ASSERT_EQ(obj.vertices.size(), tin.vertices.size());
  ASSERT_EQ(obj.faces.size(), tin.triangles.size());
  for (size_t i = 0; i < tin.vertices.size(); ++i) {
    // Shortest round-trip text reads back bit for bit.
    EXPECT_EQ(obj.vertices[i].x, tin.vertices[i].x);
    EXPECT_EQ(obj.vertices[i].y, tin.vertices[i].y);
    EXPECT_EQ(obj.vertices[i].z, tin.vertices[i].z);
  }
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(obj.faces[t][k], tin.triangles[t].v[k] + 1);
    const auto& f = obj.faces[t];
    EXPECT_GT(Cross(obj.vertices[f[0] - 1], obj.vertices[f[1] - 1], obj.vertices[f[2] - 1]), 0);
  }
  bool names_crs = false;
  for (const std::string& c : obj.comments) {
    if (c.find("EPSG:32632") != std::string::npos) names_crs = true;
    if (c.rfind("# crs_wkt: ", 0) == 0) {
      auto back = Crs::FromWkt(c.substr(11));
      ASSERT_TRUE(back.ok()) << c;
      EXPECT_TRUE(back->IsSame(*crs));
    }
  }
  EXPECT_TRUE(names_crs);
}

TEST(ExportObj, VisibleOnlyDropsTrianglesAndRenumbersVertices) {
  const Tin tin = SampleTin();
  TempDir dir;
  const std::string path = dir.Path("v.obj");
  ExportOptions options;
  options.visible_only = true;
  auto report = ExportTin(tin, nullptr, path, options);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  const ObjFile obj = ParseObj(path);
  EXPECT_EQ(obj.faces.size(), VisibleTriangleCount(tin));
  EXPECT_LT(obj.faces.size(), tin.triangles.size());
  EXPECT_EQ(obj.vertices.size(), VisibleVertexCount(tin));
  EXPECT_LT(obj.vertices.size(), tin.vertices.size());
  EXPECT_EQ(report->triangles, static_cast<int64_t>(obj.faces.size()));
  EXPECT_EQ(report->vertices, static_cast<int64_t>(obj.vertices.size()));

  // Every written vertex is used, and the faces are the visible triangles in order.
  std::set<int64_t> used;
  size_t f = 0;
  for (const TinTriangle& tri : tin.triangles) {
    if (!tri.visible) continue;
    for (int k = 0; k < 3; ++k) {
      const int64_t v = obj.faces[f][k];
      ASSERT_GE(v, 1);
      ASSERT_LE(v, static_cast<int64_t>(obj.vertices.size()));
      used.insert(v);
      ExpectSameVertex(obj.vertices[v - 1], tin.vertices[tri.v[k]]);
    }
    ++f;
  }
  EXPECT_EQ(used.size(), obj.vertices.size());
}

struct GeoJsonTriangle {
  int64_t id = 0;
  bool visible = true;
  std::optional<std::string> tag;
  std::vector<TinVertex> ring;
};

struct GeoJsonFile {
  std::vector<GeoJsonTriangle> triangles;
  std::unique_ptr<OGRSpatialReference> srs;
};

GeoJsonFile ReadGeoJson(const std::string& path) {
  GDALAllRegister();
  GeoJsonFile out;
  std::unique_ptr<GDALDataset> ds(
      GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  EXPECT_TRUE(ds) << path;
  if (!ds) return out;
  EXPECT_EQ(std::string(ds->GetDriver()->GetDescription()), "GeoJSON");
  OGRLayer* layer = ds->GetLayer(0);
  if (const OGRSpatialReference* srs = layer->GetSpatialRef()) out.srs.reset(srs->Clone());
  for (auto& feature : *layer) {
    GeoJsonTriangle t;
    t.id = feature->GetFieldAsInteger64("id");
    t.visible = feature->GetFieldAsInteger("visible") != 0;
    const int tag = feature->GetFieldIndex("tag");
    if (feature->IsFieldSetAndNotNull(tag)) t.tag = feature->GetFieldAsString(tag);
    const OGRGeometry* g = feature->GetGeometryRef();
    EXPECT_EQ(wkbFlatten(g->getGeometryType()), wkbPolygon);
    EXPECT_TRUE(g->Is3D());
    const OGRLinearRing* ring = g->toPolygon()->getExteriorRing();
    for (int i = 0; i < ring->getNumPoints(); ++i)
      t.ring.push_back({ring->getX(i), ring->getY(i), ring->getZ(i), VertexKind::kDem});
    out.triangles.push_back(std::move(t));
  }
  return out;
}

TEST(ExportGeoJson, ReadsBackThroughOgrWithPropertiesAndCrs) {
  const Tin tin = SampleTin();
  auto crs = Crs::FromUserInput("EPSG:32632");
  ASSERT_TRUE(crs.ok());
  TempDir dir;
  const std::string path = dir.Path("s.geojson");
  ExportOptions options;
  options.format = ExportFormat::kGeoJson;
  for (size_t t = 0; t < tin.triangles.size(); ++t)
    options.triangle_ids.push_back(1000 + 3 * static_cast<int64_t>(t));
  auto report = ExportTin(tin, &*crs, path, options);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->triangles, static_cast<int64_t>(tin.triangles.size()));

  const GeoJsonFile file = ReadGeoJson(path);
  ASSERT_EQ(file.triangles.size(), tin.triangles.size());
  ASSERT_TRUE(file.srs);
  auto back = Crs::FromWkt([&] {
    char* wkt = nullptr;
    file.srs->exportToWkt(&wkt);
    std::string s = wkt;
    CPLFree(wkt);
    return s;
  }());
  ASSERT_TRUE(back.ok());
  EXPECT_TRUE(back->IsSame(*crs)) << back->Label();
  EXPECT_EQ(back->Epsg().value_or(0), 32632);

  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    const GeoJsonTriangle& got = file.triangles[t];
    EXPECT_EQ(got.id, options.triangle_ids[t]);
    EXPECT_EQ(got.visible, tri.visible);
    if (tri.tag == kNoTag) {
      EXPECT_FALSE(got.tag.has_value());
    } else {
      EXPECT_EQ(got.tag.value_or("?"), tin.tags[tri.tag]);
    }
    ASSERT_EQ(got.ring.size(), 4u);  // closed
    for (int k = 0; k < 3; ++k) ExpectSameVertex(got.ring[k], tin.vertices[tri.v[k]]);
    ExpectSameVertex(got.ring[3], got.ring[0]);
    EXPECT_GT(Cross(got.ring[0], got.ring[1], got.ring[2]), 0);
  }
}

TEST(ExportGeoJson, VisibleOnlyKeepsVisibleTrianglesAndOverwrites) {
  const Tin tin = SampleTin();
  TempDir dir;
  const std::string path = dir.Path("v.geojson");
  ExportOptions options;
  options.format = ExportFormat::kGeoJson;
  ASSERT_TRUE(ExportTin(tin, nullptr, path, options).ok());  // then overwritten
  options.visible_only = true;
  auto report = ExportTin(tin, nullptr, path, options);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->triangles, static_cast<int64_t>(VisibleTriangleCount(tin)));
  EXPECT_EQ(report->vertices, static_cast<int64_t>(VisibleVertexCount(tin)));
  const GeoJsonFile file = ReadGeoJson(path);
  ASSERT_EQ(file.triangles.size(), VisibleTriangleCount(tin));
  for (const GeoJsonTriangle& t : file.triangles) {
    EXPECT_TRUE(t.visible);
    ASSERT_GE(t.id, 0);
    ASSERT_LT(t.id, static_cast<int64_t>(tin.triangles.size()));
    const TinTriangle& tri = tin.triangles[t.id];  // without store ids, the id is the index
    EXPECT_TRUE(tri.visible);
    for (int k = 0; k < 3; ++k) ExpectSameVertex(t.ring[k], tin.vertices[tri.v[k]]);
  }
}

TEST(ExportTin, UnwritablePathIsAnIOErrorNamingIt) {
  const Tin tin = SampleTin();
  TempDir dir;
  for (ExportFormat format : {ExportFormat::kObj, ExportFormat::kPly, ExportFormat::kStl,
                              ExportFormat::kGlb, ExportFormat::kGeoJson}) {
    const std::string path = dir.Path("no/such/dir/out.file");
    ExportOptions options;
    options.format = format;
    auto report = ExportTin(tin, nullptr, path, options);
    ASSERT_FALSE(report.ok());
    EXPECT_EQ(report.status().code(), StatusCode::kIOError);
    EXPECT_NE(report.status().message().find(path), std::string::npos) << report.status().message();
  }
}

// A writer that fails half way (here: nothing visible to write as GLB) leaves no file, and an
// older file at the path is left as it was.
TEST(ExportTin, AFailedExportLeavesNoFileAndKeepsTheOldOne) {
  Tin tin = SampleTin();
  for (TinTriangle& t : tin.triangles) t.visible = false;
  TempDir dir;
  const std::string fresh = dir.Path("fresh.glb");
  ExportOptions options;
  options.format = ExportFormat::kGlb;
  options.visible_only = true;
  ASSERT_FALSE(ExportTin(tin, nullptr, fresh, options).ok());
  EXPECT_FALSE(std::filesystem::exists(fresh));
  const std::string old = dir.Path("old.glb");
  std::ofstream(old) << "earlier export";
  ASSERT_FALSE(ExportTin(tin, nullptr, old, options).ok());
  std::ifstream in(old);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "earlier export");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.Path("")),
                          std::filesystem::directory_iterator()),
            1);  // no temporary file left beside it
}

TEST(ExportTin, WrongNumberOfIdsIsRefused) {
  const Tin tin = SampleTin();
  TempDir dir;
  ExportOptions options;
  options.format = ExportFormat::kGeoJson;
  options.triangle_ids = {1, 2, 3};
  auto report = ExportTin(tin, nullptr, dir.Path("x.geojson"), options);
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace tinbase
