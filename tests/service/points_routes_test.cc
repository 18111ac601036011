// The survey point routes through a real socket: POST /surfaces/{s}/points puts Point Z and
// MultiPoint Z features in as one `points` feature and DELETE /surfaces/{s}/points/{id} takes it
// out, each one transaction with its tiles (the store checks clean after each); bad bodies are
// refused naming the place and change nothing; writes need the token and are refused read-only.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/service_support.h"
#include "tests/support/store_target.h"
#include "tests/support/stored_feature.h"

namespace tinbase::testing {
namespace {

const char* const kPoints = "/surfaces/t/points";

// A MultiPoint Z feature of the store's CRS (EPSG:32632): shots around kLandX, kLandY, about
// the ground's height.
nlohmann::json Shots(double dx = 0) {
  return {{"type", "Feature"},
          {"properties", {{"surveyor", "ab"}}},
          {"geometry",
           {{"type", "MultiPoint"},
            {"coordinates",
             {{kLandX + dx + 10.25, kLandY + 20.5, 561.5},
              {kLandX + dx + 400.75, kLandY - 300.25, 572.25}}}}}};
}

class PointsRoutesTest : public ::testing::Test {
 protected:
  void Serve(service::ServiceOptions options = {}) {
    options.store_path = store_;
    service_ = std::make_unique<TestService>(options);
    ASSERT_TRUE(service_->running());
  }
  void ExpectStoreChecksClean() {
    const CliResult check = RunCli("check --full " + Quote(store_));
    EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  }
  EditorFeature LoadStored(int64_t id) { return LoadStoredFeature(store_, "t", id); }
  // A request that must be refused with `status` and a message containing `expected`, leaving
  // the store as it was.
  void ExpectRefused(const httplib::Result& r, int status, const std::string& expected) {
    ExpectJsonError(r, status, expected);
    EXPECT_EQ(TableChecksums(store_), before_) << "a refused request changed the store";
  }
  void RefuseBody(const nlohmann::json& body, const std::string& expected,
                  const std::string& query = "") {
    ExpectRefused(PostGeoJson(*service_->Client(), kPoints + query, body), 400, expected);
  }

  TempDir dir_;
  std::string store_ = StoreTarget(dir_, "s.tinbase");
  std::unique_ptr<TestService> service_;
  std::map<std::string, std::string> before_;
};

TEST_F(PointsRoutesTest, PostPutsThePointsInAndDeleteTakesThemOut) {
  ASSERT_NO_FATAL_FAILURE(CopyDemoStore(store_));
  ASSERT_NO_FATAL_FAILURE(Serve());
  const nlohmann::json body = {{"type", "FeatureCollection"}, {"features", {Shots(), Shots(900)}}};
  const nlohmann::json a =
      JsonAnswer(PostGeoJson(*service_->Client(), std::string(kPoints) + "?tag=gnss", body), 201);
  ASSERT_TRUE(HasFields(
      a, {"features", "points_in", "vertices", "snapped", "tiles_updated", "bbox", "tx"}));
  ASSERT_EQ(a["features"].size(), 1u) << a.dump();
  ASSERT_EQ(a["bbox"].size(), 4u) << a.dump();
  EXPECT_EQ(a["points_in"], 4);
  EXPECT_EQ(a["vertices"], 4);
  EXPECT_EQ(a["snapped"], nlohmann::json::array());
  EXPECT_EQ(a["tiles_updated"], 0) << "the store has no tiles";
  EXPECT_LE(a["bbox"][0].get<double>(), kLandX + 10.25);
  EXPECT_GE(a["bbox"][2].get<double>(), kLandX + 1300.75);
  ExpectStoreChecksClean();
  const int64_t id = a["features"][0].get<int64_t>();
  const EditorFeature f = LoadStored(id);
  EXPECT_EQ(f.mode, FeatureMode::kPoints);
  EXPECT_EQ(f.tag, "gnss");
  ASSERT_EQ(f.points.size(), 4u);
  EXPECT_EQ(f.points[1].z, 572.25) << "the point keeps its own z";
  const nlohmann::json changes = Json(RunCli("changes --json " + Quote(store_)));
  ASSERT_TRUE(changes.is_array() && !changes.empty()) << changes.dump();
  ASSERT_TRUE(HasFields(changes.back(), {"tx", "action"}));
  EXPECT_EQ(changes.back()["tx"], a["tx"]);
  EXPECT_EQ(changes.back()["action"], "points add");

  const nlohmann::json removed =
      JsonAnswer(service_->Client()->Delete(std::string(kPoints) + "/" + std::to_string(id)));
  ASSERT_TRUE(HasFields(removed, {"removed_features", "features", "vertices", "tx"}));
  EXPECT_EQ(removed["removed_features"], nlohmann::json({id}));
  EXPECT_EQ(removed["features"], nlohmann::json::array());
  EXPECT_EQ(removed["vertices"], 4);
  EXPECT_GT(removed["tx"].get<int64_t>(), a["tx"].get<int64_t>());
  ExpectStoreChecksClean();
  EXPECT_EQ(Json(RunCli("info --json " + Quote(store_)))["surfaces"][0]["features"], 0);
}

// Lon/lat in, reprojected; a single Point Z is a body too.
TEST_F(PointsRoutesTest, ACrsParameterReprojectsThePoints) {
  ASSERT_NO_FATAL_FAILURE(CopyDemoStore(store_));
  ASSERT_NO_FATAL_FAILURE(Serve());
  const nlohmann::json point = {
      {"type", "Feature"},
      {"properties", nullptr},
      {"geometry", {{"type", "Point"}, {"coordinates", {7.25, 43.85, 601.5}}}}};
  const nlohmann::json a = JsonAnswer(
      PostGeoJson(*service_->Client(), std::string(kPoints) + "?crs=EPSG:4326", point), 201);
  ASSERT_TRUE(HasFields(a, {"vertices", "features"}));
  ASSERT_EQ(a["features"].size(), 1u) << a.dump();
  EXPECT_EQ(a["vertices"], 1);
  const EditorFeature f = LoadStored(a["features"][0].get<int64_t>());
  ASSERT_EQ(f.points.size(), 1u);
  EXPECT_GT(f.points[0].x, 1e5) << "projected metres, not degrees";
  EXPECT_EQ(f.points[0].z, 601.5);
  ExpectStoreChecksClean();
}

// The tiles are brought up to date in the edit's transaction: the pyramid's transaction is the
// edit's and nothing is left for `tiles update`; a tile update that fails refuses the edit.
TEST_F(PointsRoutesTest, TheTilesCommitWithTheEdit) {
  ASSERT_NO_FATAL_FAILURE(CopyDemoStoreWithTiles(store_));
  ASSERT_NO_FATAL_FAILURE(Serve());
  nlohmann::json near_lake = Shots();
  near_lake["geometry"]["coordinates"] = {{kDemoLakeX + 5000.5, kDemoLakeY + 10.25, 300.5}};
  const nlohmann::json a = JsonAnswer(PostGeoJson(*service_->Client(), kPoints, near_lake), 201);
  ASSERT_TRUE(HasFields(a, {"tiles_updated", "tx", "features"}));
  ASSERT_EQ(a["features"].size(), 1u) << a.dump();
  EXPECT_GT(a["tiles_updated"].get<int64_t>(), 0) << a.dump();
  const nlohmann::json info = Json(RunCli("tiles info " + Quote(store_) + " --surface t --json"));
  ASSERT_TRUE(HasFields(info, {"layer"}));
  ASSERT_TRUE(HasFields(info["layer"], {"tinbase"}));
  ASSERT_TRUE(HasFields(info["layer"]["tinbase"], {"tx"}));
  EXPECT_EQ(info["layer"]["tinbase"]["tx"], a["tx"]) << info.dump();
  const nlohmann::json changes = Json(RunCli("changes --json " + Quote(store_)));
  ASSERT_TRUE(changes.is_array() && !changes.empty()) << changes.dump();
  ASSERT_TRUE(HasFields(changes.back(), {"tx"}));
  EXPECT_EQ(changes.back()["tx"], a["tx"]);
  EXPECT_EQ(Json(RunCli("tiles update " + Quote(store_) + " --surface t --json"))["changes"], 0);

  {
    auto store = Store::Open(store_);
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    ASSERT_TRUE((*store)->db().Exec("UPDATE tile_pyramids SET extensions = 'bogus'").ok());
  }
  before_ = TableChecksums(store_);
  const std::string id = std::to_string(a["features"][0].get<int64_t>());
  ExpectRefused(service_->Client()->Delete(std::string(kPoints) + "/" + id), 400,
                "updating the tiles of the edit: unknown tile extension 'bogus'");
  ExpectRefused(PostGeoJson(*service_->Client(), kPoints, Shots()), 400,
                "updating the tiles of the edit");
  ExpectStoreChecksClean();
}

TEST_F(PointsRoutesTest, BadBodiesAndFeaturesAreRefusedNamingThePlace) {
  ASSERT_NO_FATAL_FAILURE(CopyDemoStoreWithFeature(store_));
  ASSERT_NO_FATAL_FAILURE(Serve());
  before_ = TableChecksums(store_);
  auto client = service_->Client();
  ExpectRefused(client->Post(kPoints, "{\"type\": \"Feature\",", "application/json"), 400,
                "malformed JSON");
  ExpectRefused(client->Post(kPoints, Shots().dump(), "text/plain"), 415, "not 'text/plain'");
  nlohmann::json flat = Shots();
  flat["geometry"]["coordinates"][1] = {kLandX, kLandY};
  RefuseBody(flat, "feature, point 1: (360000, 4862000) has no z");
  nlohmann::json line = Shots();
  line["geometry"]["type"] = "LineString";
  RefuseBody(line, "feature: geometry is a LineString; survey points are a Point or MultiPoint");
  nlohmann::json empty = Shots();
  empty["geometry"]["coordinates"] = nlohmann::json::array();
  RefuseBody({{"type", "FeatureCollection"}, {"features", {Shots(), empty}}},
             "features[1]: the geometry is empty");
  nlohmann::json text = Shots();
  text["geometry"]["coordinates"][0][2] = "high";
  RefuseBody(text, "feature, vertex 0: coordinate \"high\" is not a finite number");
  nlohmann::json outside = Shots();
  outside["geometry"]["coordinates"][1] = {kLandX + 900000, kLandY, 500};
  RefuseBody(outside, "feature, point 1: (1260000, 4862000) lies outside surface 't'");
  nlohmann::json deep = Shots();
  deep["geometry"]["coordinates"][0][2] = -1e7;
  RefuseBody(deep, "feature, point 0: z -10000000 is far outside the relief");
  RefuseBody(Shots(), "parameter 'crs'", "?crs=EPSG:0");
  ExpectRefused(PostGeoJson(*client, "/surfaces/nope/points", Shots()), 404,
                "no surface named 'nope'");

  ExpectRefused(client->Delete(std::string(kPoints) + "/99"), 404, "no feature 99 in surface 't'");
  ExpectRefused(client->Delete(std::string(kPoints) + "/x"), 400, "feature id");
  // The granite square is a fill polygon: DELETE /features/{id} takes it out, not this route.
  ExpectRefused(client->Delete(std::string(kPoints) + "/1"), 400, "not survey points");
}

TEST_F(PointsRoutesTest, WritesNeedTheTokenAreRefusedReadOnlyAndLargeBodiesToo) {
  ASSERT_NO_FATAL_FAILURE(CopyDemoStore(store_));
  service::ServiceOptions options;
  options.token = "s3cret-token";
  options.max_body_bytes = 4096;
  ASSERT_NO_FATAL_FAILURE(Serve(options));
  before_ = TableChecksums(store_);
  ExpectRefused(PostGeoJson(*service_->Client(), kPoints, Shots()), 401, "needs an Authorization");
  ExpectRefused(service_->Client()->Delete(std::string(kPoints) + "/1"), 401,
                "needs an Authorization");
  nlohmann::json large = Shots();
  large["properties"]["padding"] = std::string(8192, 'x');
  ExpectRefused(PostGeoJson(*service_->Client(), kPoints, large, "s3cret-token"), 413,
                "larger than");
  JsonAnswer(PostGeoJson(*service_->Client(), kPoints, Shots(), "s3cret-token"), 201);
  service_.reset();

  options.token.reset();
  options.read_only = true;
  ASSERT_NO_FATAL_FAILURE(Serve(options));
  before_ = TableChecksums(store_);
  ExpectRefused(PostGeoJson(*service_->Client(), kPoints, Shots()), 403, "--read-only");
  ExpectRefused(service_->Client()->Delete(std::string(kPoints) + "/1"), 403, "--read-only");
}

}  // namespace
}  // namespace tinbase::testing
