// The DEM routes through a real socket, each answer read by a reader tinbase did not write:
// the overview PNG and the clipped GeoTIFF by gdalinfo, the TIN of a box by the Khronos glTF
// validator; the same windows and face counts as `tinbase dem clip`; bad requests 400/404 with
// the service still serving.
#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "tests/core/export/gltf_check.h"
#include "tests/support/gdal_tools.h"
#include "tests/support/service_support.h"
#include "tests/support/store_target.h"

namespace tinbase::testing {
namespace {

// A land window of the demo DEM in its CRS (EPSG:32632), 20 km square.
constexpr const char* kLandBox = "340000,4840000,360000,4860000";

std::vector<double> Numbers(const std::string& text) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ',')) out.push_back(std::stod(part));
  return out;
}

std::string HeaderOf(const httplib::Headers& headers, const char* name) {
  const auto it = headers.find(name);
  return it == headers.end() ? "" : it->second;
}

class DemRoutesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    CopyDemoStore(store_);
    service::ServiceOptions options;
    options.store_path = store_;
    service_ = std::make_unique<TestService>(options);
    ASSERT_TRUE(service_->running());
  }

  // GETs `path`, which must answer 200 with `content_type`, and saves the body as `name`.
  std::string Fetch(const std::string& path, const std::string& content_type,
                    const std::string& name, httplib::Headers* headers = nullptr) {
    auto r = service_->Client()->Get(path.c_str());
    if (!r) {
      ADD_FAILURE() << path << ": no answer";
      return "";
    }
    EXPECT_EQ(r->status, 200) << path << ": " << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), content_type) << path;
    if (headers != nullptr) *headers = r->headers;
    const std::string file = dir_.Path(name);
    std::ofstream(file, std::ios::binary) << r->body;
    return file;
  }

  // gdalinfo -json of `file` (a failure when gdalinfo is missing or cannot read it).
  nlohmann::json GdalInfo(const std::string& file, const std::string& flags = "") {
    if (!HaveTool("gdalinfo")) return nullptr;
    const ToolResult r = RunTool("gdalinfo -json " + flags + " " + Quote(file));
    EXPECT_EQ(r.exit_code, 0) << r.out;
    auto j = nlohmann::json::parse(r.out, nullptr, false);
    EXPECT_FALSE(j.is_discarded()) << r.out;
    return j;
  }

  TempDir dir_;
  std::string store_;
  std::unique_ptr<TestService> service_;
};

TEST_F(DemRoutesTest, ListsTheDemsWithTheirBoxesInTheStoreCrsAndInLonLat) {
  const nlohmann::json info = Json(RunCli("info --json " + Quote(store_)));
  const nlohmann::json answer = JsonAnswer(service_->Client()->Get("/dems"));
  ASSERT_EQ(answer["dems"].size(), 1u);
  const nlohmann::json& d = answer["dems"][0];
  EXPECT_EQ(d["name"], "N43E007");
  EXPECT_EQ(d["width"], info["dems"][0]["width"]);
  EXPECT_EQ(d["height"], info["dems"][0]["height"]);
  EXPECT_EQ(d["levels"], info["dems"][0]["levels"]);
  EXPECT_EQ(d["crs"], "EPSG:32632");
  EXPECT_EQ(d["bbox"], info["dems"][0]["bbox"]);
  // The SRTM sheet is the degree square 7-8 E, 43-44 N. Warped to UTM its grid is a box that
  // holds the square, turned by the grid convergence; that box in lon/lat holds it too, with a
  // few hundredths of a degree to spare.
  const auto ll = d["bbox_lonlat"].get<std::vector<double>>();
  ASSERT_EQ(ll.size(), 4u);
  EXPECT_LE(ll[0], 7.0);
  EXPECT_LE(ll[1], 43.0);
  EXPECT_GE(ll[2], 8.0);
  EXPECT_GE(ll[3], 44.0);
  EXPECT_NEAR(ll[0], 7, 0.05);
  EXPECT_NEAR(ll[1], 43, 0.05);
  EXPECT_NEAR(ll[2], 8, 0.05);
  EXPECT_NEAR(ll[3], 44, 0.05);
}

TEST_F(DemRoutesTest, TheOverviewIsAHillshadePngInLonLatThatGdalReads) {
  httplib::Headers headers;
  const std::string png =
      Fetch("/dems/N43E007/overview.png?size=400", "image/png", "overview.png", &headers);
  // Levels halve 1391 rows: 1391, 696, 348, ...: the finest within 400 pixels is level 2.
  EXPECT_EQ(HeaderOf(headers, "X-Tinbase-Level"), std::string("2"));
  const std::vector<double> bbox = Numbers(HeaderOf(headers, "X-Tinbase-Bbox-Lonlat"));
  ASSERT_EQ(bbox.size(), 4u);
  const nlohmann::json info = GdalInfo(png, "-stats");
  ASSERT_TRUE(info.is_object());
  EXPECT_EQ(info["driverShortName"], "PNG");
  ASSERT_EQ(info["bands"].size(), 2u);
  EXPECT_EQ(info["bands"][0]["type"], "Byte");
  EXPECT_EQ(info["bands"][1]["colorInterpretation"], "Alpha");
  // Not blank: the shade varies, and most of the image is opaque.
  EXPECT_GT(info["bands"][0]["stdDev"].get<double>(), 10);
  EXPECT_GT(info["bands"][1]["mean"].get<double>(), 128);
  EXPECT_LE(std::max(info["size"][0].get<int>(), info["size"][1].get<int>()), 400 * 3 / 2);
  // The image covers the DEM's grid: the box /dems gives, to a cell of the level (about 0.003
  // degrees).
  const auto dem_box = JsonAnswer(service_->Client()->Get("/dems"))["dems"][0]["bbox_lonlat"]
                           .get<std::vector<double>>();
  ASSERT_EQ(dem_box.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(bbox[i], dem_box[i], 0.01) << i;

  // An explicit level, when it fits; a repeated request with the tag is a 304.
  auto r = service_->Client()->Get("/dems/N43E007/overview.png?level=3");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(r->get_header_value("X-Tinbase-Level"), "3");
  auto again = service_->Client()->Get("/dems/N43E007/overview.png?level=3",
                                       {{"If-None-Match", r->get_header_value("ETag")}});
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 304);
}

TEST_F(DemRoutesTest, AClipIsTheGeoTiffTheCliWritesAndGdalReadsIt) {
  httplib::Headers headers;
  const std::string path = std::string("/dems/N43E007/clip?bbox=") + kLandBox;
  const std::string served = Fetch(path, "image/tiff", "served.tif", &headers);
  const std::string cli = dir_.Path("cli.tif");
  RunCli("dem clip " + Quote(store_) + " --bbox " + kLandBox + " -o " + Quote(cli));
  const nlohmann::json a = GdalInfo(served, "-checksum");
  const nlohmann::json b = GdalInfo(cli, "-checksum");
  ASSERT_TRUE(a.is_object() && b.is_object());
  EXPECT_EQ(a["driverShortName"], "GTiff");
  EXPECT_EQ(a["size"], b["size"]);
  EXPECT_EQ(a["geoTransform"], b["geoTransform"]);
  EXPECT_EQ(a["bands"][0]["type"], "Float32");
  EXPECT_EQ(a["bands"][0]["checksum"], b["bands"][0]["checksum"]);
  EXPECT_NE(a["bands"][0]["checksum"], 0) << "a land window is not flat";
  EXPECT_NE(a["coordinateSystem"]["wkt"].get<std::string>().find("32632"), std::string::npos);
  EXPECT_EQ(HeaderOf(headers, "X-Tinbase-Level"), std::string("0"));

  // Over the cell budget, the window is read from a coarser level: 248 x 248 cells of level 0
  // are about 62 x 62 of level 2, the first within 5000.
  const std::string coarse = Fetch(path + "&max_cells=5000", "image/tiff", "coarse.tif", &headers);
  EXPECT_EQ(HeaderOf(headers, "X-Tinbase-Level"), std::string("2"));
  const nlohmann::json c = GdalInfo(coarse);
  ASSERT_TRUE(c.is_object());
  EXPECT_LE(c["size"][0].get<int>() * c["size"][1].get<int>(), 5000);
  EXPECT_NEAR(c["geoTransform"][1].get<double>(), 4 * a["geoTransform"][1].get<double>(), 1e-6);
}

TEST_F(DemRoutesTest, AClipBoxMayBeGivenInLonLat) {
  httplib::Headers headers;
  const std::string tif = Fetch("/dems/N43E007/clip?bbox=7.2,43.7,7.3,43.8&crs=EPSG:4326",
                                "image/tiff", "lonlat.tif", &headers);
  const nlohmann::json info = GdalInfo(tif);
  ASSERT_TRUE(info.is_object());
  // The corners of the written window, back in lon/lat, hold the asked box (to a cell).
  const auto& corners = info["wgs84Extent"]["coordinates"][0];
  double west = 180, east = -180, south = 90, north = -90;
  for (const auto& p : corners) {
    west = std::min(west, p[0].get<double>()), east = std::max(east, p[0].get<double>());
    south = std::min(south, p[1].get<double>()), north = std::max(north, p[1].get<double>());
  }
  const double cell = 0.0015;  // 81 m in degrees, generously
  EXPECT_LE(west, 7.2 + cell);
  EXPECT_GE(east, 7.3 - cell);
  EXPECT_LE(south, 43.7 + cell);
  EXPECT_GE(north, 43.8 - cell);
  EXPECT_LT(east - west, 0.1 + 0.05);
}

TEST_F(DemRoutesTest, TheTinOfABoxIsAValidGlbAtTheFaceBudgetWithItsOrigin) {
  httplib::Headers headers;
  const std::string path =
      std::string("/dems/N43E007/tin?bbox=") + kLandBox + "&faces=500&max_cells=4096";
  const std::string glb = Fetch(path, "model/gltf-binary", "box.glb", &headers);
  ExpectValidGltf(glb);
  const auto header = [&](const char* name) { return HeaderOf(headers, name); };
  EXPECT_LE(std::stoi(header("X-Tinbase-Faces")), 500);
  EXPECT_GT(std::stoi(header("X-Tinbase-Faces-In")), 500);
  // 248 x 248 cells over 4096: level 2's 62 x 62.
  EXPECT_EQ(std::string(header("X-Tinbase-Level")), "2");
  const std::vector<double> origin = Numbers(header("X-Tinbase-Origin"));
  ASSERT_EQ(origin.size(), 3u);
  const GlbFile file = ParseGlb(glb);
  const nlohmann::json& o = file.gltf["asset"]["extras"]["tinbase"]["origin"];
  EXPECT_EQ(origin[0], o["longitude"].get<double>());
  EXPECT_EQ(origin[1], o["latitude"].get<double>());
  EXPECT_EQ(origin[2], o["height"].get<double>());
  EXPECT_NEAR(origin[0], 7.14, 0.05);
  EXPECT_NEAR(origin[1], 43.79, 0.05);
  EXPECT_GT(origin[2], 100);

  // The CLI's paper-002 clip of the same window and budget has as many faces.
  const nlohmann::json cli = Json(RunCli("dem clip " + Quote(store_) + " --bbox " + kLandBox +
                                         " --max-cells 4096 --faces 500 --format glb --json -o " +
                                         Quote(dir_.Path("cli.glb"))));
  EXPECT_EQ(cli["faces"].get<int>(), std::stoi(header("X-Tinbase-Faces")));
  EXPECT_EQ(cli["level"], 2);

  // In lon/lat, with the paper's strategy.
  const std::string lonlat = Fetch(
      "/dems/N43E007/tin?bbox=7.2,43.7,7.3,43.8&crs=EPSG:4326&faces=300&max_cells=2500"
      "&strategy=paper",
      "model/gltf-binary", "lonlat.glb", &headers);
  ExpectValidGltf(lonlat);
  EXPECT_LE(std::stoi(header("X-Tinbase-Faces")), 300);
}

TEST_F(DemRoutesTest, BadRequestsAreJsonErrorsAndTheServiceKeepsServing) {
  auto client = service_->Client();
  ExpectJsonError(client->Get("/dems/nope/overview.png"), 404, "nope");
  ExpectJsonError(client->Get("/dems/nope/clip?bbox=0,0,1,1"), 404, "nope");
  ExpectJsonError(client->Get("/dems/N43E007/overview.png?level=9"), 400, "parameter 'level'");
  ExpectJsonError(client->Get("/dems/N43E007/overview.png?level=0"), 400,
                  "1391 cells on its longer side");
  ExpectJsonError(client->Get("/dems/N43E007/overview.png?size=0"), 400, "parameter 'size'");
  ExpectJsonError(client->Get("/dems/N43E007/overview.png?size=99999"), 400, "out of range");
  ExpectJsonError(client->Get("/dems/N43E007/clip"), 400, "missing parameter 'bbox'");
  ExpectJsonError(client->Get("/dems/N43E007/clip?bbox=nan,0,1,1"), 400, "parameter 'bbox'");
  ExpectJsonError(client->Get("/dems/N43E007/clip?bbox=1,1,1,1"), 400, "no area");
  ExpectJsonError(client->Get("/dems/N43E007/clip?bbox=0,0,10,10"), 400, "N43E007");
  ExpectJsonError(client->Get(std::string("/dems/N43E007/clip?bbox=") + kLandBox + "&max_cells=0"),
                  400, "parameter 'max_cells'");
  ExpectJsonError(
      client->Get(std::string("/dems/N43E007/clip?bbox=") + kLandBox + "&crs=EPSG:999999"), 400,
      "parameter 'crs'");
  // GDAL would read a file named as a CRS; the service does not.
  ExpectJsonError(
      client->Get(std::string("/dems/N43E007/clip?bbox=") + kLandBox + "&crs=/etc/passwd"), 400,
      "parameter 'crs'");
  ExpectJsonError(client->Get(std::string("/dems/N43E007/tin?bbox=") + kLandBox + "&faces=1"), 400,
                  "parameter 'faces'");
  ExpectJsonError(
      client->Get(std::string("/dems/N43E007/tin?bbox=") + kLandBox + "&strategy=fastest"), 400,
      "parameter 'strategy'");
  ExpectJsonError(
      client->Get(std::string("/dems/N43E007/tin?bbox=") + kLandBox + "&max_cells=99999999"), 400,
      "parameter 'max_cells'");
  JsonAnswer(client->Get("/dems"));
}

}  // namespace
}  // namespace tinbase::testing
