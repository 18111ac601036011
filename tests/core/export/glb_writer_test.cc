// The GLB writer's files pass the Khronos glTF validator with no error, and read back (a plain
// split of the GLB into its JSON and binary chunks) to the same surface: every vertex, taken from
// the ENU frame back through GeographicLib and GDAL to the store's CRS, lands on its TIN vertex
// within a millimetre; the frame's origin and the CRS are in asset.extras; one material per tag;
// each triangle's feature id and the property table say which feature it belongs to.
#include "core/export/glb_writer.h"

#include <gtest/gtest.h>

#include <GeographicLib/LocalCartesian.hpp>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "core/export/export_feature.h"
#include "core/export/mesh_selection.h"
#include "core/export/obj_writer.h"
#include "core/geometry/reproject.h"
#include "tests/core/export/gltf_check.h"
#include "tests/core/export/sample_tin.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using nlohmann::json;
using testing::GlbFile;

// The axis-aligned rectangle [x0, x1] x [y0, y1] as one polygon.
std::shared_ptr<const PolygonLocator> Rectangle(double x0, double y0, double x1, double y1) {
  Polygon p;
  p.shell = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  return std::make_shared<PolygonLocator>(std::vector<Polygon>{p});
}

// Two overlapping fill features (the later wins where they overlap), an erase feature and a
// breakline, over the sample surface's west and middle.
GlbContent SampleFeatures(const Tin& tin) {
  const double x0 = 612345.678901234, y0 = 5171234.56789012, cell = 30.123456789012345;
  GlbContent c;
  ExportFeature a;
  a.id = 11;
  a.tag = "granite";
  a.attributes = {{"formation", "Brockman"}, {"age ma", 2460.5}, {"drilled", true}};
  a.inside = Rectangle(x0 - 1, y0 - 1, x0 + 5 * cell, y0 + 9 * cell + 1);
  ExportFeature b;
  b.id = 12;
  b.tag = "schist";
  b.attributes = {{"formation", "Marra Mamba"}, {"age ma", 2597}};
  b.inside = Rectangle(x0 + 3 * cell, y0 + 2 * cell, x0 + 8 * cell, y0 + 6 * cell);
  ExportFeature e;
  e.id = 13;
  e.mode = FeatureMode::kErase;
  e.inside = Rectangle(x0 + 9 * cell, y0, x0 + 12 * cell, y0 + 3 * cell);
  ExportFeature line;
  line.id = 14;
  line.mode = FeatureMode::kBreakline;
  c.features = {a, b, e, line};
  c.triangle_feature = OwningFeatures(tin, c.features);
  return c;
}

struct Corner {
  double x, y, z;  // back in the store's CRS
};

// Every POSITION of the GLB, back from glTF axes and the ENU frame to the store's CRS.
std::vector<std::vector<Corner>> CornersInStoreCrs(const GlbFile& glb, const Crs& crs) {
  const json& t = glb.gltf["asset"]["extras"]["tinbase"];
  const json& o = t["origin"];
  const GeographicLib::LocalCartesian frame(
      o["latitude"].get<double>(), o["longitude"].get<double>(), o["height"].get<double>());
  auto geographic = Crs::FromUserInput(t["geographic_crs"].get<std::string>());
  EXPECT_TRUE(geographic.ok());
  std::vector<std::vector<Corner>> out;
  for (const json& prim : glb.gltf["meshes"][0]["primitives"]) {
    const std::vector<double> p = glb.Accessor(prim["attributes"]["POSITION"].get<int>());
    std::vector<TinVertex> back;
    for (size_t i = 0; i + 2 < p.size(); i += 3) {
      double lat = 0, lon = 0, h = 0;
      frame.Reverse(p[i], -p[i + 2], p[i + 1], lat, lon, h);  // x east, y up, z -north
      back.push_back({lon, lat, h, VertexKind::kDem});
    }
    EXPECT_TRUE(ReprojectXy(*geographic, crs, back).ok());
    std::vector<Corner> corners;
    for (const TinVertex& v : back) corners.push_back({v.x, v.y, v.z});
    out.push_back(corners);
  }
  return out;
}

class GlbWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    tin_ = testing::SampleExportTin();
    auto crs = Crs::FromUserInput("EPSG:32632");
    ASSERT_TRUE(crs.ok());
    crs_ = std::make_unique<Crs>(*crs);
    content_ = SampleFeatures(tin_);
  }

  GlbFile WriteAndRead(const MeshSelection& s, const GlbContent& content, const Crs* crs) {
    const std::string path = dir_.Path("s.glb");
    Status written = WriteGlb(tin_, crs, s, content, path);
    EXPECT_TRUE(written.ok()) << written.ToString();
    testing::ExpectValidGltf(path);
    return testing::ParseGlb(path);
  }

  Tin tin_;
  std::unique_ptr<Crs> crs_;
  GlbContent content_;
  testing::TempDir dir_;
};

TEST_F(GlbWriterTest, VerticesGoBackToTheStoreCrsWithinAMillimetre) {
  const MeshSelection s = SelectTriangles(tin_, false);
  const GlbFile glb = WriteAndRead(s, content_, crs_.get());
  const json& t = glb.gltf["asset"]["extras"]["tinbase"];
  EXPECT_EQ(t["crs"], "EPSG:32632");
  EXPECT_EQ(t["epsg"], 32632);
  EXPECT_EQ(t["frame"], "ENU");
  EXPECT_EQ(t["geographic_crs"], "EPSG:4326");
  auto wkt = Crs::FromWkt(t["crs_wkt"].get<std::string>());
  ASSERT_TRUE(wkt.ok());
  EXPECT_TRUE(wkt->IsSame(*crs_));
  const double cell = 30.123456789012345;
  EXPECT_DOUBLE_EQ(t["origin"]["x"].get<double>(), 612345.678901234 + 6 * cell);
  EXPECT_DOUBLE_EQ(t["origin"]["y"].get<double>(), 5171234.56789012 + 4.5 * cell);
  EXPECT_NEAR(t["origin"]["latitude"].get<double>(), 46.68, 0.01);  // UTM 32N, Alps
  EXPECT_NEAR(t["origin"]["longitude"].get<double>(), 10.47, 0.01);

  size_t corners = 0;
  double worst = 0;
  std::set<size_t> reached;
  for (const auto& prim : CornersInStoreCrs(glb, *crs_)) {
    for (const Corner& c : prim) {
      ++corners;
      // The nearest TIN vertex (the surface is small: a plain scan).
      size_t best = 0;
      double best_d = 1e300;
      for (size_t v = 0; v < tin_.vertices.size(); ++v) {
        const TinVertex& p = tin_.vertices[v];
        const double d = std::hypot(c.x - p.x, c.y - p.y, c.z - p.z);
        if (d < best_d) best_d = d, best = v;
      }
      worst = std::max(worst, best_d);
      reached.insert(best);
    }
  }
  EXPECT_LT(worst, 1e-3);
  EXPECT_EQ(reached.size(), tin_.vertices.size());
  EXPECT_GE(corners, tin_.vertices.size());  // split where tags and features meet
}

TEST_F(GlbWriterTest, OneMaterialPerTagAndTheInvisibleApart) {
  const MeshSelection s = SelectTriangles(tin_, false);
  const GlbFile glb = WriteAndRead(s, content_, crs_.get());
  std::map<std::string, size_t> triangles_of;
  size_t total = 0;
  for (const json& prim : glb.gltf["meshes"][0]["primitives"]) {
    const json& m = glb.gltf["materials"][prim["material"].get<int>()];
    const size_t n = glb.gltf["accessors"][prim["indices"].get<int>()]["count"].get<size_t>() / 3;
    triangles_of[m["name"].get<std::string>()] += n;
    total += n;
    const std::vector<double> normals = glb.Accessor(prim["attributes"]["NORMAL"].get<int>());
    for (size_t i = 0; i + 2 < normals.size(); i += 3) EXPECT_GT(normals[i + 1], 0.3);  // up
  }
  EXPECT_EQ(total, tin_.triangles.size());
  std::map<std::string, size_t> want;
  for (const TinTriangle& t : tin_.triangles)
    ++want[!t.visible ? "invisible" : t.tag == kNoTag ? "untagged" : tin_.tags[t.tag]];
  EXPECT_EQ(triangles_of, want);
  // A tag's colour depends on its value only.
  std::map<std::string, json> colour;
  for (const json& m : glb.gltf["materials"])
    colour[m["name"]] = m["pbrMetallicRoughness"]["baseColorFactor"];
  EXPECT_NE(colour["granite"], colour["schist"]);
  Tin renamed = tin_;
  renamed.tags = {"schist", "granite"};
  const std::string path = dir_.Path("renamed.glb");
  ASSERT_TRUE(WriteGlb(renamed, crs_.get(), s, {}, path).ok());
  const GlbFile again = testing::ParseGlb(path);
  for (const json& m : again.gltf["materials"])
    EXPECT_EQ(m["pbrMetallicRoughness"]["baseColorFactor"], colour[m["name"]]) << m["name"];
}

// The property table, decoded from its buffer views as EXT_structural_metadata lays them out.
struct FeatureTable {
  std::vector<int64_t> id;
  std::vector<uint8_t> mode;
  std::map<std::string, std::vector<std::string>> strings;
  std::map<std::string, std::vector<double>> numbers;
};

FeatureTable ReadTable(const GlbFile& glb) {
  FeatureTable out;
  const json& meta = glb.gltf["extensions"]["EXT_structural_metadata"];
  const json& table = meta["propertyTables"][0];
  const json& cls = meta["schema"]["classes"][table["class"].get<std::string>()]["properties"];
  const size_t count = table["count"].get<size_t>();
  for (const auto& [name, prop] : table["properties"].items()) {
    const std::string values = glb.View(prop["values"].get<int>());
    const json& def = cls[name];
    if (def["type"] == "STRING") {
      const auto offsets = glb.Values<uint32_t>(glb.View(prop["stringOffsets"].get<int>()));
      EXPECT_EQ(offsets.size(), count + 1) << name;
      for (size_t i = 0; i < count; ++i)
        out.strings[name].push_back(values.substr(offsets[i], offsets[i + 1] - offsets[i]));
    } else if (def["type"] == "ENUM") {
      out.mode = glb.Values<uint8_t>(values);
    } else if (def["componentType"] == "INT64") {
      out.id = glb.Values<int64_t>(values);
    } else {
      EXPECT_EQ(def["componentType"], "FLOAT64") << name;
      out.numbers[def.value("name", name)] = glb.Values<double>(values);
    }
  }
  for (const json& v : glb.gltf["bufferViews"]) EXPECT_EQ(v.value("byteOffset", 0) % 8, 0);
  return out;
}

TEST_F(GlbWriterTest, FeatureIdsAndThePropertyTableSayWhichFeatureEachTriangleIs) {
  const MeshSelection s = SelectTriangles(tin_, true);
  const GlbFile glb = WriteAndRead(s, content_, crs_.get());
  const json& used = glb.gltf["extensionsUsed"];
  EXPECT_NE(std::find(used.begin(), used.end(), "EXT_mesh_features"), used.end());
  EXPECT_NE(std::find(used.begin(), used.end(), "EXT_structural_metadata"), used.end());

  const FeatureTable table = ReadTable(glb);
  EXPECT_EQ(table.id, (std::vector<int64_t>{11, 12, 13, 14}));
  EXPECT_EQ(table.mode, (std::vector<uint8_t>{static_cast<uint8_t>(FeatureMode::kFill),
                                              static_cast<uint8_t>(FeatureMode::kFill),
                                              static_cast<uint8_t>(FeatureMode::kErase),
                                              static_cast<uint8_t>(FeatureMode::kBreakline)}));
  EXPECT_EQ(table.strings.at("tag"), (std::vector<std::string>{"granite", "schist", "", ""}));
  EXPECT_EQ(table.strings.at("formation"),
            (std::vector<std::string>{"Brockman", "Marra Mamba", "", ""}));
  EXPECT_EQ(table.strings.at("drilled"), (std::vector<std::string>{"true", "", "", ""}));
  // "age ma" is missing on two rows, so it is text; its id has no space.
  EXPECT_EQ(table.strings.at("age_ma"), (std::vector<std::string>{"2460.5", "2597", "", ""}));
  const json& modes =
      glb.gltf["extensions"]["EXT_structural_metadata"]["schema"]["enums"]["featureMode"]["values"];
  EXPECT_EQ(modes.size(), kFeatureModes.size());

  // Per primitive, each triangle's three corners carry one id, and the ids match the features
  // the triangles were assigned to (counted per feature over the whole mesh).
  std::map<int, size_t> per_feature;
  for (const json& prim : glb.gltf["meshes"][0]["primitives"]) {
    if (!prim["attributes"].contains("_FEATURE_ID_0")) continue;
    const json& ids = prim["extensions"]["EXT_mesh_features"]["featureIds"][0];
    EXPECT_EQ(ids["nullFeatureId"], 4);
    EXPECT_EQ(ids["propertyTable"], 0);
    const std::vector<double> f = glb.Accessor(prim["attributes"]["_FEATURE_ID_0"].get<int>());
    const std::vector<double> idx = glb.Accessor(prim["indices"].get<int>());
    std::set<int> distinct;
    for (size_t i = 0; i + 2 < idx.size(); i += 3) {
      const double a = f[static_cast<size_t>(idx[i])];
      EXPECT_EQ(f[static_cast<size_t>(idx[i + 1])], a);
      EXPECT_EQ(f[static_cast<size_t>(idx[i + 2])], a);
      ++per_feature[static_cast<int>(a)];
      if (a != 4) distinct.insert(static_cast<int>(a));
    }
    EXPECT_EQ(ids["featureCount"].get<size_t>(), distinct.size());
  }
  std::map<int, size_t> want;
  for (uint32_t t : s.triangles)
    ++want[content_.triangle_feature[t] == kNoFeature ? 4 : content_.triangle_feature[t]];
  EXPECT_EQ(per_feature, want);
  EXPECT_GT(want[0], 0u);
  EXPECT_GT(want[1], 0u);
  EXPECT_EQ(want.count(2), 0u);  // erase and breakline own nothing
}

TEST_F(GlbWriterTest, WithoutCrsTheFrameIsTheStoreAxesShifted) {
  const MeshSelection s = SelectTriangles(tin_, false);
  const GlbFile glb = WriteAndRead(s, {}, nullptr);
  const json& t = glb.gltf["asset"]["extras"]["tinbase"];
  EXPECT_FALSE(t.contains("crs"));
  EXPECT_FALSE(t.contains("epsg"));
  EXPECT_EQ(t["frame"], "store axes shifted to the origin (no CRS)");
  EXPECT_FALSE(glb.gltf.contains("extensionsUsed"));
  const json& prim = glb.gltf["meshes"][0]["primitives"][0];
  const std::vector<double> p = glb.Accessor(prim["attributes"]["POSITION"].get<int>());
  double worst = 1e300;
  const TinVertex& v0 = tin_.vertices[0];
  for (size_t i = 0; i + 2 < p.size(); i += 3) {
    const double x = p[i] + t["origin"]["x"].get<double>();
    const double y = -p[i + 2] + t["origin"]["y"].get<double>();
    worst = std::min(worst, std::hypot(x - v0.x, y - v0.y));
  }
  EXPECT_LT(worst, 1e-3);  // vertex 0 is in there, where it was
}

// A store in longitude and latitude: no projection step, the frame straight on WGS 84.
TEST_F(GlbWriterTest, AGeographicStoreGoesStraightIntoTheFrame) {
  tin_ = testing::MakeGridTin(8, 6, 0.0003, 10.0, 46.0, [](double x, double y) {
    return 1500 + (x - 10.0) * 1e4 + (y - 46.0) * 5e3;
  });
  const Tin& geo = tin_;
  auto wgs84 = Crs::FromUserInput("EPSG:4326");
  ASSERT_TRUE(wgs84.ok());
  const GlbFile glb = WriteAndRead(SelectTriangles(geo, false), {}, &*wgs84);
  const json& t = glb.gltf["asset"]["extras"]["tinbase"];
  EXPECT_EQ(t["geographic_crs"], "EPSG:4326");
  EXPECT_NEAR(t["origin"]["longitude"].get<double>(), 10.0 + 4 * 0.0003, 1e-12);
  EXPECT_NEAR(t["origin"]["latitude"].get<double>(), 46.0 + 3 * 0.0003, 1e-12);
  const std::vector<std::vector<Corner>> back = CornersInStoreCrs(glb, *wgs84);
  ASSERT_EQ(back.size(), 1u);
  ASSERT_EQ(back[0].size(), geo.vertices.size());  // one primitive, nothing split
  for (const Corner& c : back[0]) {
    bool found = false;
    for (const TinVertex& v : geo.vertices)
      found = found || (std::abs(c.x - v.x) < 1e-8 && std::abs(c.y - v.y) < 1e-8 &&
                        std::abs(c.z - v.z) < 1e-3);
    EXPECT_TRUE(found) << c.x << " " << c.y << " " << c.z;
  }
}

// Projected numbers in a store that says it is geographic are no place on the earth.
TEST_F(GlbWriterTest, CoordinatesOffTheEarthAreRefused) {
  auto wgs84 = Crs::FromUserInput("EPSG:4326");
  ASSERT_TRUE(wgs84.ok());
  const std::string path = dir_.Path("off.glb");
  const Status s = WriteGlb(tin_, &*wgs84, SelectTriangles(tin_, false), {}, path);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("is not a place on the earth in EPSG:4326"), std::string::npos)
      << s.message();
}

TEST_F(GlbWriterTest, NothingToWriteIsAnError) {
  Tin hidden = tin_;
  for (TinTriangle& t : hidden.triangles) t.visible = false;
  const Status s =
      WriteGlb(hidden, crs_.get(), SelectTriangles(hidden, true), {}, dir_.Path("none.glb"));
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
}

TEST_F(GlbWriterTest, IsSmallerThanObjOfTheSameSurface) {
  const Tin big = testing::MakeGridTin(
      260, 260, 2.5, 612345.678901234, 5171234.56789012,
      [](double x, double y) { return 800 + std::sin(x / 40) * 20 + std::cos(y / 30) * 7; });
  const MeshSelection s = SelectTriangles(big, false);
  const std::string glb = dir_.Path("big.glb"), obj = dir_.Path("big.obj");
  ASSERT_TRUE(WriteGlb(big, crs_.get(), s, {}, glb).ok());
  ASSERT_TRUE(WriteObj(big, crs_.get(), s, obj).ok());
  testing::ExpectValidGltf(glb);
  EXPECT_LT(std::filesystem::file_size(glb), std::filesystem::file_size(obj));
  // 261 x 261 vertices: 16-bit indices would not reach them all, so the writer chose 32-bit.
  const GlbFile file = testing::ParseGlb(glb);
  const json& prim = file.gltf["meshes"][0]["primitives"][0];
  EXPECT_EQ(file.gltf["accessors"][prim["indices"].get<int>()]["componentType"], 5125);
}

}  // namespace
}  // namespace tinbase
