// The surface read routes through a real socket: what a client learns of the store's surfaces,
// where a point lies, the triangles by id and by window, the features and the tags. Answers are
// compared with the CLI's on the same store, and lon/lat with gdaltransform's.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <sstream>

#include "tests/support/gdal_tools.h"
#include "tests/support/service_support.h"
#include "tests/support/store_target.h"

namespace tinbase::testing {
namespace {

class SurfaceRoutesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    CopyDemoStoreWithFeature(store_);
    service::ServiceOptions options;
    options.store_path = store_;
    service_ = std::make_unique<TestService>(options);
    ASSERT_TRUE(service_->running());
  }
  nlohmann::json Get(const std::string& path, int status = 200) {
    return JsonAnswer(service_->Client()->Get(path), status);
  }
  std::string Surface() const { return Quote(store_) + " --surface t --json"; }

  TempDir dir_;
  std::string store_;
  std::unique_ptr<TestService> service_;
};

// lon, lat of an EPSG:32632 point by gdaltransform (PROJ through GDAL's own tool).
std::pair<double, double> GdalLonLat(double x, double y) {
  EXPECT_TRUE(HaveTool("gdaltransform")) << "gdaltransform is missing (apt-get install gdal-bin)";
  std::ostringstream cmd;
  cmd.precision(17);
  cmd << "echo " << x << " " << y << " | gdaltransform -s_srs EPSG:32632 -t_srs EPSG:4326 "
      << "-output_xy";
  const ToolResult r = RunTool(cmd.str());
  std::istringstream in(r.out);
  double lon = 0, lat = 0;
  in >> lon >> lat;
  return {lon, lat};
}

TEST_F(SurfaceRoutesTest, ListsTheSurfacesWithTheCountsInfoPrints) {
  const nlohmann::json info = Json(RunCli("info --json " + Quote(store_)));
  const nlohmann::json answer = Get("/surfaces");
  ASSERT_EQ(answer["surfaces"].size(), 1u);
  const nlohmann::json& s = answer["surfaces"][0];
  EXPECT_EQ(s["name"], "t");
  EXPECT_EQ(s["triangles"], info["surfaces"][0]["triangles"]);
  EXPECT_EQ(s["vertices"], info["surfaces"][0]["vertices"]);
  EXPECT_EQ(s["features"], 1);
  EXPECT_EQ(s["tolerance"], 20.0);
  EXPECT_EQ(s["crs"], info["crs"]);
  // The surface covers the DEM it was built on, to within one cell.
  ASSERT_EQ(s["extent"].size(), 6u);
  const nlohmann::json& dem = info["dems"][0];
  const double cell = dem["cell_size"][0].get<double>();
  for (int i : {0, 1}) {
    EXPECT_NEAR(s["extent"][i].get<double>(), dem["bbox"][i].get<double>(), cell);          // min
    EXPECT_NEAR(s["extent"][3 + i].get<double>(), dem["bbox"][2 + i].get<double>(), cell);  // max
  }
  EXPECT_LT(s["extent"][2].get<double>(), s["extent"][5].get<double>());
  // The DEM is the 1-degree SRTM cell N43E007: its lon/lat box, give or take a cell.
  const std::vector<double> lonlat = s["extent_lonlat"].get<std::vector<double>>();
  ASSERT_EQ(lonlat.size(), 4u);
  EXPECT_NEAR(lonlat[0], 7, 0.05);
  EXPECT_NEAR(lonlat[1], 43, 0.05);
  EXPECT_NEAR(lonlat[2], 8, 0.05);
  EXPECT_NEAR(lonlat[3], 44, 0.05);
  EXPECT_EQ(s["tiles"], nlohmann::json::array());  // no pyramid built
}

// The counts and extent are kept between calls while the change log stands still: an edit made
// by another process moves the log, and the next answer shows it.
TEST_F(SurfaceRoutesTest, TheListFollowsAnEditMadeOutsideTheService) {
  const nlohmann::json first = Get("/surfaces")["surfaces"][0];
  EXPECT_EQ(Get("/surfaces")["surfaces"][0], first) << "the kept answer is the read one";
  auto r = service_->Client()->Get("/surfaces/t/features");
  ASSERT_TRUE(r);
  const nlohmann::json features = nlohmann::json::parse(r->body);
  ASSERT_EQ(features["features"].size(), 1u) << r->body;
  const int64_t id = features["features"][0]["id"].get<int64_t>();
  RunWrite(store_, "polygon remove " + Quote(store_) + " " + std::to_string(id));
  const nlohmann::json info = Json(RunCli("info --json " + Quote(store_)))["surfaces"][0];
  const nlohmann::json after = Get("/surfaces")["surfaces"][0];
  EXPECT_EQ(after["features"], 0);
  EXPECT_EQ(after["triangles"], info["triangles"]);
  EXPECT_EQ(after["vertices"], info["vertices"]);
  EXPECT_NE(after["triangles"], first["triangles"]) << "the removal re-triangulated the region";
  EXPECT_EQ(Get("/surfaces/t")["features"], 0);
}

TEST_F(SurfaceRoutesTest, OneSurfaceByName) {
  const nlohmann::json s = Get("/surfaces/t");
  EXPECT_EQ(s["name"], "t");
  EXPECT_GT(s["triangles"].get<int64_t>(), 1000);
  EXPECT_EQ(s["extent_lonlat"].size(), 4u);
}

TEST_F(SurfaceRoutesTest, AnUnknownSurfaceOrPathIsAJson404) {
  ExpectJsonError(service_->Client()->Get("/surfaces/nope"), 404, "no surface named 'nope'");
  ExpectJsonError(service_->Client()->Get("/surfaces/nope/locate?x=1&y=2"), 404,
                  "no surface named 'nope'");
  ExpectJsonError(service_->Client()->Get("/no/such/route"), 404, "no route for GET");
}

TEST_F(SurfaceRoutesTest, LocateAnswersWhatTheCliAnswers) {
  const nlohmann::json cli = Json(RunCli("locate " + Surface() + " 360000 4862000"));
  const nlohmann::json a = Get("/surfaces/t/locate?x=360000&y=4862000");
  EXPECT_EQ(a["x"], 360000.0);
  EXPECT_EQ(a["y"], 4862000.0);
  EXPECT_EQ(a["z"], cli["z"]);
  const nlohmann::json& t = a["triangle"];
  EXPECT_EQ(t["id"], cli["triangle"]);
  EXPECT_EQ(t["visible"], cli["visible"]);
  EXPECT_EQ(t["tag"], cli["tag"]);
  // Corners and neighbours as `neighbours` prints them.
  const nlohmann::json nb =
      Json(RunCli("neighbours " + Surface() + " " + std::to_string(t["id"].get<int64_t>())));
  EXPECT_EQ(t["neighbours"], nb["neighbours"]);
  ASSERT_EQ(t["vertices"].size(), 3u);
  for (int i = 0; i < 3; ++i) {
    // edges[i] runs from corner i + 1 to corner i + 2.
    EXPECT_EQ(t["vertices"][(i + 1) % 3], nb["edges"][i]["from"]);
    EXPECT_EQ(t["vertices"][(i + 2) % 3], nb["edges"][i]["to"]);
  }
  // z lies within the corners' heights.
  std::vector<double> zs;
  for (const auto& v : t["vertices"]) zs.push_back(v[2].get<double>());
  EXPECT_GE(a["z"].get<double>(), *std::min_element(zs.begin(), zs.end()));
  EXPECT_LE(a["z"].get<double>(), *std::max_element(zs.begin(), zs.end()));
}

TEST_F(SurfaceRoutesTest, TheTrianglesLonLatIsGdalsAndLonLatLocatesTheSamePoint) {
  const nlohmann::json t = Get("/surfaces/t/locate?x=360000&y=4862000")["triangle"];
  ASSERT_EQ(t["lonlat"].size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const auto [lon, lat] =
        GdalLonLat(t["vertices"][i][0].get<double>(), t["vertices"][i][1].get<double>());
    EXPECT_NEAR(t["lonlat"][i][0].get<double>(), lon, 1e-7);
    EXPECT_NEAR(t["lonlat"][i][1].get<double>(), lat, 1e-7);
    EXPECT_EQ(t["lonlat"][i][2], t["vertices"][i][2]);  // heights unchanged
  }
  const auto [lon, lat] = GdalLonLat(360000, 4862000);
  std::ostringstream path;
  path.precision(17);
  path << "/surfaces/t/locate?lon=" << lon << "&lat=" << lat;
  const nlohmann::json a = Get(path.str());
  EXPECT_EQ(a["triangle"]["id"], t["id"]);
  EXPECT_NEAR(a["x"].get<double>(), 360000, 1e-3);
  EXPECT_NEAR(a["y"].get<double>(), 4862000, 1e-3);
  // The same with x, y and crs=.
  path.str("");
  path << "/surfaces/t/locate?crs=EPSG:4326&x=" << lon << "&y=" << lat;
  EXPECT_EQ(Get(path.str())["triangle"]["id"], t["id"]);
}

TEST_F(SurfaceRoutesTest, APointOutsideTheSurfaceIs404Outside) {
  const nlohmann::json e = Get("/surfaces/t/locate?x=0&y=0", 404);
  EXPECT_EQ(e["error"]["code"], "outside");
  EXPECT_NE(e["error"]["message"].get<std::string>().find("outside surface 't'"),
            std::string::npos);
}

TEST_F(SurfaceRoutesTest, PostLocateAnswersEveryPointAsTheCliDoes) {
  const std::vector<std::pair<double, double>> points = {
      {360000, 4862000}, {0, 0}, {361000, 4861000}, {380123.5, 4850456.25}, {359000, 4863500}};
  nlohmann::json body = {{"points", nlohmann::json::array()}};
  std::ofstream file(dir_.Path("points.csv"));
  file.precision(17);
  for (const auto& [x, y] : points) {
    body["points"].push_back({x, y});
    file << x << "," << y << "\n";
  }
  file.close();
  const nlohmann::json a =
      JsonAnswer(service_->Client()->Post("/surfaces/t/locate", body.dump(), "application/json"));
  const CliResult cli = RunCli("locate " + Surface() + " --points " + dir_.Path("points.csv"));
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  std::istringstream lines(cli.out);
  std::string line;
  ASSERT_EQ(a["results"].size(), points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    ASSERT_TRUE(std::getline(lines, line));
    const nlohmann::json c = nlohmann::json::parse(line);
    const nlohmann::json& r = a["results"][i];
    EXPECT_EQ(r["x"], c["x"]);
    EXPECT_EQ(r["y"], c["y"]);
    EXPECT_EQ(r["triangle"], c["triangle"]) << i;
    EXPECT_EQ(r["z"], c["z"]) << i;
    EXPECT_EQ(r["tag"], c["tag"]) << i;
  }
  EXPECT_EQ(a["results"][1]["triangle"], nullptr);  // (0, 0) is outside
  EXPECT_EQ(a["results"][1]["z"], nullptr);
  EXPECT_EQ(a["results"][2]["tag"], "granite");
}

TEST_F(SurfaceRoutesTest, PostLocateTakesLonLatWithCrs) {
  const auto [lon, lat] = GdalLonLat(360000, 4862000);
  const nlohmann::json body = {{"points", {{lon, lat}}}, {"crs", "EPSG:4326"}};
  const nlohmann::json a =
      JsonAnswer(service_->Client()->Post("/surfaces/t/locate", body.dump(), "application/json"));
  const nlohmann::json one = Get("/surfaces/t/locate?x=360000&y=4862000");
  EXPECT_EQ(a["results"][0]["triangle"], one["triangle"]["id"]);
  EXPECT_NEAR(a["results"][0]["x"].get<double>(), 360000, 1e-3);
}

TEST_F(SurfaceRoutesTest, ATriangleByIdComesWithItsNeighbours) {
  const int64_t id = Get("/surfaces/t/locate?x=360000&y=4862000")["triangle"]["id"];
  const nlohmann::json a = Get("/surfaces/t/triangles/" + std::to_string(id));
  EXPECT_EQ(a["triangle"]["id"], id);
  ASSERT_EQ(a["neighbours"].size(), 3u);
  const nlohmann::json nb = Json(RunCli("neighbours " + Surface() + " " + std::to_string(id)));
  for (int i = 0; i < 3; ++i) {
    ASSERT_FALSE(a["neighbours"][i].is_null());  // an inner triangle
    EXPECT_EQ(a["neighbours"][i]["id"], nb["neighbours"][i]);
    EXPECT_EQ(a["neighbours"][i]["vertices"].size(), 3u);
    // Each neighbour names this triangle among its own.
    const auto& back = a["neighbours"][i]["neighbours"];
    EXPECT_NE(std::find(back.begin(), back.end(), nlohmann::json(id)), back.end());
  }
  ExpectJsonError(service_->Client()->Get("/surfaces/t/triangles/999999999"), 404,
                  "triangle 999999999");
}

TEST_F(SurfaceRoutesTest, TheTrianglesOfAWindowAreTheClisWithTheirTrueNeighbours) {
  const std::string bbox = "359000,4861000,361000,4863000";
  const nlohmann::json a = Get("/surfaces/t/triangles?bbox=" + bbox);
  const nlohmann::json cli = Json(RunCli("triangles " + Surface() + " --bbox " + bbox));
  ASSERT_EQ(a["triangles"].size(), cli["triangles"].size());
  ASSERT_GT(a["triangles"].size(), 10u);
  std::set<int64_t> ids;
  for (size_t i = 0; i < a["triangles"].size(); ++i) {
    const nlohmann::json& t = a["triangles"][i];
    EXPECT_EQ(t["id"], cli["triangles"][i]["id"]);
    EXPECT_EQ(t["vertices"], cli["triangles"][i]["corners"]);
    ids.insert(t["id"].get<int64_t>());
  }
  // A triangle on the window's edge keeps the neighbours outside it: the same as in a larger
  // window (where the CLI's selection cuts them).
  const nlohmann::json wide = Get("/surfaces/t/triangles?bbox=357000,4859000,363000,4865000");
  std::map<int64_t, nlohmann::json> wide_neighbours;
  for (const auto& t : wide["triangles"]) wide_neighbours[t["id"]] = t["neighbours"];
  size_t outside = 0;
  for (const auto& t : a["triangles"]) {
    EXPECT_EQ(t["neighbours"], wide_neighbours[t["id"]]) << t["id"];
    for (const auto& n : t["neighbours"]) {
      ASSERT_FALSE(n.is_null());  // the window is far from the surface's boundary
      outside += ids.count(n.get<int64_t>()) == 0 ? 1 : 0;
    }
  }
  EXPECT_GT(outside, 0u);
}

TEST_F(SurfaceRoutesTest, AWindowOverTheLimitIs413AndAnEmptyOneIsEmpty) {
  const nlohmann::json e =
      Get("/surfaces/t/triangles?bbox=359000,4861000,361000,4863000&limit=5", 413);
  EXPECT_NE(e["error"]["message"].get<std::string>().find("more than limit=5"), std::string::npos);
  EXPECT_EQ(Get("/surfaces/t/triangles?bbox=0,0,1,1")["triangles"], nlohmann::json::array());
  ExpectJsonError(service_->Client()->Get("/surfaces/t/triangles"), 400,
                  "missing parameter 'bbox'");
}

TEST_F(SurfaceRoutesTest, TheFeaturesAreGeoJsonThatOgrReads) {
  ASSERT_TRUE(HaveTool("ogrinfo")) << "ogrinfo is missing (apt-get install gdal-bin)";
  auto r = service_->Client()->Get("/surfaces/t/features");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->get_header_value("Content-Type"), "application/geo+json");
  const std::string file = dir_.Path("features.geojson");
  std::ofstream(file) << r->body;
  const ToolResult info = RunTool("ogrinfo -al " + Quote(file));
  EXPECT_NE(info.out.find("Feature Count: 1"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("Geometry: Polygon"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("tag (String) = granite"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("mode (String) = fill"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("unit (String) = u0"), std::string::npos) << info.out;
  const nlohmann::json j = nlohmann::json::parse(r->body);
  const auto& ring = j["features"][0]["geometry"]["coordinates"][0];
  EXPECT_EQ(ring.front(), ring.back());  // closed, as GeoJSON asks
  EXPECT_EQ(ring.size(), 5u);
  EXPECT_EQ(ring[0][0], kGraniteMinX);
  // In lon/lat: near 7.26 E, 43.9 N.
  auto geo_answer = service_->Client()->Get("/surfaces/t/features?crs=EPSG:4326");
  ASSERT_TRUE(geo_answer);
  const nlohmann::json geo = nlohmann::json::parse(geo_answer->body);
  const auto& p = geo["features"][0]["geometry"]["coordinates"][0][0];
  EXPECT_NEAR(p[0].get<double>(), GdalLonLat(kGraniteMinX, kGraniteMinY).first, 1e-7);
  EXPECT_NEAR(p[1].get<double>(), GdalLonLat(kGraniteMinX, kGraniteMinY).second, 1e-7);
}

TEST_F(SurfaceRoutesTest, TheTagsCountTheirTriangles) {
  const nlohmann::json a = Get("/surfaces/t/tags");
  ASSERT_EQ(a["tags"].size(), 1u);
  EXPECT_EQ(a["tags"][0]["tag"], "granite");
  const nlohmann::json cli = Json(RunCli("triangles " + Surface() + " --tag granite --bbox " +
                                         "300000,4700000,450000,4900000"));
  EXPECT_EQ(a["tags"][0]["triangles"], cli["count"]);
  const nlohmann::json visible =
      Json(RunCli("triangles " + Surface() + " --tag granite " +
                  "--visible-only --bbox 300000,4700000,450000,4900000"));
  EXPECT_EQ(a["tags"][0]["visible_triangles"], visible["count"]);
}

}  // namespace
}  // namespace tinbase::testing
