// The edit routes through a real socket: features posted, replaced and removed go through the
// CLI's engine (the store checks clean after each), bad bodies are refused naming the place and
// change nothing, writes need the token, and concurrent writes to one region all land.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <thread>
#include <vector>

#include "db/change_log.h"
#include "tests/support/service_support.h"
#include "tests/support/store_target.h"
#include "tests/support/stored_feature.h"

namespace tinbase::testing {
namespace {

constexpr double kLon = 7.25, kLat = 43.85;  // on land in N43E007
const char* const kPost = "/surfaces/t/features?crs=EPSG:4326";

class EditRoutesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    CopyDemoStore(store_);
  }
  void Serve(service::ServiceOptions options = {}) {
    options.store_path = store_;
    service_ = std::make_unique<TestService>(options);
    ASSERT_TRUE(service_->running());
  }
  void ExpectStoreChecksClean() {
    const CliResult check = RunCli("check --full " + Quote(store_));
    EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  }
  int64_t Features() {
    return Json(RunCli("info --json " + Quote(store_)))["surfaces"][0]["features"].get<int64_t>();
  }
  EditorFeature LoadStored(int64_t id) { return LoadStoredFeature(store_, "t", id); }
  // A request that must be refused with `status` and a message containing `expected`, leaving
  // the store as it was and the service serving.
  void ExpectRefused(const httplib::Result& r, int status, const std::string& expected) {
    ExpectJsonError(r, status, expected);
    EXPECT_EQ(TableChecksums(store_), before_) << "a refused request changed the store";
    JsonAnswer(service_->Client()->Get("/surfaces/t"));
  }
  void RefuseBody(const nlohmann::json& body, const std::string& expected,
                  const std::string& query = "?crs=EPSG:4326") {
    ExpectRefused(PostGeoJson(*service_->Client(), "/surfaces/t/features" + query, body), 400,
                  expected);
  }

  TempDir dir_;
  std::string store_;
  std::unique_ptr<TestService> service_;
  std::map<std::string, std::string> before_;
};

TEST_F(EditRoutesTest, PostsAFeatureCollectionAsOneTransactionWithItsBox) {
  Serve();
  const nlohmann::json body = {
      {"type", "FeatureCollection"},
      {"features",
       {LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}, {"tag", "lake"}, {"name", "north"}}),
        LonLatSquare(kLon + 0.02, kLat, 0.004, {{"mode", "erase"}})}}};
  const nlohmann::json a = JsonAnswer(PostGeoJson(*service_->Client(), kPost, body), 201);
  ASSERT_EQ(a["features"].size(), 2u) << a.dump();
  EXPECT_GT(a["tx"].get<int64_t>(), 1);
  EXPECT_EQ(a["tiles_updated"], 0) << "the store has no tiles";
  // The box is in the store's CRS (UTM 32N metres) and holds both squares; in lon/lat likewise.
  const auto& box = a["bbox_lonlat"];
  ASSERT_EQ(box.size(), 4u);
  EXPECT_LE(box[0].get<double>(), kLon - 0.004);
  EXPECT_GE(box[2].get<double>(), kLon + 0.024);
  EXPECT_LE(box[1].get<double>(), kLat - 0.004);
  EXPECT_GE(box[3].get<double>(), kLat + 0.004);
  EXPECT_GT(a["bbox"][0].get<double>(), 1e5) << "projected metres, not degrees";
  EXPECT_EQ(Features(), 2);
  ExpectStoreChecksClean();

  const EditorFeature lake = LoadStored(a["features"][0].get<int64_t>());
  EXPECT_EQ(lake.mode, FeatureMode::kFill);
  EXPECT_EQ(lake.tag, "lake");
  EXPECT_EQ(lake.attributes, nlohmann::json({{"name", "north"}}));
  EXPECT_EQ(LoadStored(a["features"][1].get<int64_t>()).mode, FeatureMode::kErase);
  // One change in the log, as `polygon add` writes it.
  const nlohmann::json changes = Json(RunCli("changes --json " + Quote(store_)));
  EXPECT_EQ(changes.back()["tx"], a["tx"]) << changes.dump();
  EXPECT_EQ(changes.back()["action"], "polygon add");
}

TEST_F(EditRoutesTest, CoordinatesWithoutCrsAreTheStoresAndQueryModeAndTagApply) {
  Serve();
  // The same square written in the store's UTM coordinates, by the answer of a lon/lat post.
  const nlohmann::json first =
      JsonAnswer(PostGeoJson(*service_->Client(), std::string(kPost) + "&mode=fill",
                             LonLatSquare(kLon, kLat, 0.004)),
                 201);
  const auto& b = first["bbox"];
  const double x = 0.5 * (b[0].get<double>() + b[2].get<double>());
  const double y = 0.5 * (b[1].get<double>() + b[3].get<double>());
  const nlohmann::json utm = {
      {"type", "Feature"},
      {"properties", nullptr},
      {"geometry",
       {{"type", "LineString"}, {"coordinates", {{x - 300, y - 200, 5}, {x + 300, y + 250}}}}}};
  const nlohmann::json a = JsonAnswer(
      PostGeoJson(*service_->Client(), "/surfaces/t/features?mode=breakline&tag=fault", utm), 201);
  const EditorFeature fault = LoadStored(a["features"][0].get<int64_t>());
  EXPECT_EQ(fault.mode, FeatureMode::kBreakline);
  EXPECT_EQ(fault.tag, "fault");
  ASSERT_EQ(fault.lines.size(), 1u);
  EXPECT_DOUBLE_EQ(fault.lines[0][0].x, x - 300);
  EXPECT_DOUBLE_EQ(fault.lines[0][0].y, y - 200);
  ExpectStoreChecksClean();
}

// 3D lines: LineString Z with properties.z_from "feature" (or the query's z_from) keep their own
// z, and a PUT without z_from keeps the old line's; a line without z, z_from on a polygon and an
// unknown source are refused naming the place.
TEST_F(EditRoutesTest, ThreeDLinesKeepTheirZThroughPostAndPut) {
  Serve();
  const auto line = [](const nlohmann::json& coordinates, nlohmann::json properties) {
    return nlohmann::json{{"type", "Feature"},
                          {"properties", std::move(properties)},
                          {"geometry", {{"type", "LineString"}, {"coordinates", coordinates}}}};
  };
  const nlohmann::json first = {{kLandX - 300, kLandY - 200, 548.5},
                                {kLandX + 300, kLandY + 250, 561.25}};
  const nlohmann::json a =
      JsonAnswer(PostGeoJson(*service_->Client(), "/surfaces/t/features",
                             line(first, {{"mode", "breakline"}, {"z_from", "feature"}})),
                 201);
  const int64_t id = a["features"][0].get<int64_t>();
  const EditorFeature own = LoadStored(id);
  EXPECT_EQ(own.z_from, ZFrom::kFeature);
  EXPECT_EQ(own.line_z, (std::vector<std::vector<double>>{{548.5, 561.25}}));
  ExpectStoreChecksClean();

  // Replaced without z_from: still 3D, with the new z.
  const nlohmann::json second = {{kLandX - 250, kLandY + 300, 552},
                                 {kLandX, kLandY + 20, 555.5},
                                 {kLandX + 280, kLandY - 240, 549}};
  const nlohmann::json put =
      JsonAnswer(service_->Client()->Put("/surfaces/t/features/" + std::to_string(id),
                                         line(second, nullptr).dump(), "application/json"));
  const EditorFeature kept = LoadStored(put["features"][0].get<int64_t>());
  EXPECT_EQ(kept.mode, FeatureMode::kBreakline);
  EXPECT_EQ(kept.z_from, ZFrom::kFeature);
  EXPECT_EQ(kept.line_z, (std::vector<std::vector<double>>{{552, 555.5, 549}}));
  ExpectStoreChecksClean();

  // The query's z_from, with lon/lat positions: the heights are not reprojected away.
  const nlohmann::json lonlat = {{kLon + 0.01, kLat, 530.5}, {kLon + 0.014, kLat + 0.003, 540}};
  const nlohmann::json b = JsonAnswer(
      PostGeoJson(*service_->Client(), std::string(kPost) + "&mode=softline&z_from=feature",
                  line(lonlat, nullptr)),
      201);
  const EditorFeature soft = LoadStored(b["features"][0].get<int64_t>());
  EXPECT_EQ(soft.mode, FeatureMode::kSoftline);
  EXPECT_EQ(soft.line_z, (std::vector<std::vector<double>>{{530.5, 540}}));
  ExpectStoreChecksClean();

  before_ = TableChecksums(store_);
  const nlohmann::json flat = {{kLandX - 300, kLandY - 900}, {kLandX + 300, kLandY - 650}};
  RefuseBody(line(flat, {{"mode", "breakline"}, {"z_from", "feature"}}),
             "feature, line 0: no z (z from the feature needs LineString Z)", "");
  RefuseBody(line(first, {{"mode", "breakline"}, {"z_from", "up"}}),
             "feature: properties.z_from: unknown z source 'up'", "");
  RefuseBody(LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}, {"z_from", "feature"}}),
             "feature: z from the feature is for lines, not mode fill");
  RefuseBody(line(first, {{"mode", "breakline"}}), "parameter 'z_from'", "?z_from=sky");
  nlohmann::json nan_z = line(first, {{"mode", "breakline"}, {"z_from", "feature"}});
  nan_z["geometry"]["coordinates"][1][2] = nullptr;
  RefuseBody(nan_z, "feature, line 0, vertex 1: coordinate null is not a finite number", "");
}

TEST_F(EditRoutesTest, ReplaceTakesItsLevelFromThePropertiesOrTheQuery) {
  Serve();
  const nlohmann::json body = {{"type", "FeatureCollection"},
                               {"features",
                                {LonLatSquare(kLon, kLat, 0.003),
                                 LonLatSquare(kLon + 0.01, kLat, 0.003, {{"level", 300}})}}};
  const nlohmann::json a = JsonAnswer(
      PostGeoJson(*service_->Client(), std::string(kPost) + "&mode=replace&level=250", body), 201);
  ASSERT_EQ(a["features"].size(), 2u) << a.dump();
  EXPECT_EQ(LoadStored(a["features"][0].get<int64_t>()).level, 250.0);
  EXPECT_EQ(LoadStored(a["features"][1].get<int64_t>()).level, 300.0);
  ExpectStoreChecksClean();
}

TEST_F(EditRoutesTest, PutReplacesAndDeleteRemovesUpdatingTheTiles) {
  RunWrite(store_, "tiles build " + Quote(store_) + " --surface t --max-zoom 10");
  Serve();
  const nlohmann::json added =
      JsonAnswer(PostGeoJson(*service_->Client(), kPost,
                             LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}, {"tag", "lake"}})),
                 201);
  EXPECT_GT(added["tiles_updated"].get<int64_t>(), 0);
  const int64_t id = added["features"][0].get<int64_t>();
  const std::string path = "/surfaces/t/features/" + std::to_string(id) + "?crs=EPSG:4326";
  const nlohmann::json replaced = JsonAnswer(service_->Client()->Put(
      path, LonLatSquare(kLon + 0.01, kLat, 0.003).dump(), "application/json"));
  EXPECT_EQ(replaced["removed_features"], nlohmann::json({id}));
  ASSERT_EQ(replaced["features"].size(), 1u);
  const int64_t new_id = replaced["features"][0].get<int64_t>();
  EXPECT_NE(new_id, id);
  EXPECT_GT(replaced["tiles_updated"].get<int64_t>(), 0);
  const EditorFeature kept = LoadStored(new_id);
  EXPECT_EQ(kept.mode, FeatureMode::kFill) << "mode and tag stay when the body gives none";
  EXPECT_EQ(kept.tag, "lake");
  EXPECT_EQ(Features(), 1);

  const nlohmann::json removed =
      JsonAnswer(service_->Client()->Delete("/surfaces/t/features/" + std::to_string(new_id)));
  EXPECT_EQ(removed["removed_features"], nlohmann::json({new_id}));
  EXPECT_EQ(removed["features"], nlohmann::json::array());
  EXPECT_EQ(Features(), 0);
  ExpectStoreChecksClean();
  // The tiles were brought up to date before each answer: nothing is left for `tiles update`.
  const nlohmann::json update =
      Json(RunCli("tiles update " + Quote(store_) + " --surface t --json"));
  EXPECT_EQ(update["changes"], 0) << update.dump();

  before_ = TableChecksums(store_);
  ExpectRefused(service_->Client()->Delete("/surfaces/t/features/" + std::to_string(new_id)), 404,
                "no feature " + std::to_string(new_id) + " in surface 't'");
  ExpectRefused(service_->Client()->Delete("/surfaces/t/features/abc"), 400, "feature id");
  // Dots in the path match no route: a path part never climbs.
  ExpectRefused(service_->Client()->Delete("/surfaces/t/features/../../1"), 404, "no route");
  ExpectRefused(service_->Client()->Delete("/surfaces/../t/features/1"), 404, "no route");
  ExpectRefused(service_->Client()->Delete("/surfaces/nope/features/1"), 404,
                "no surface named 'nope'");
}

// The tile update runs inside the edit's transaction: when it fails the edit is rolled back with
// it (no tile is left stale beside a committed edit), and when it succeeds both land as one
// transaction, the pyramid showing the edit's change.
TEST_F(EditRoutesTest, AnEditAndItsTilesCommitTogetherOrNotAtAll) {
  RunWrite(store_, "tiles build " + Quote(store_) + " --surface t --max-zoom 10");
  const auto set_extensions = [&](const std::string& names) {
    auto store = Store::Open(store_);
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    ASSERT_TRUE((*store)->db().Exec("UPDATE tile_pyramids SET extensions = '" + names + "'").ok());
  };
  // A pyramid row the update cannot read makes every tile update fail.
  set_extensions("octvertexnormals,bogus");
  Serve();
  before_ = TableChecksums(store_);
  const nlohmann::json square = LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}});
  ExpectRefused(PostGeoJson(*service_->Client(), kPost, square), 400,
                "updating the tiles of the edit: unknown tile extension 'bogus'");
  EXPECT_EQ(Features(), 0);
  ExpectStoreChecksClean();

  set_extensions("octvertexnormals");
  const nlohmann::json added = JsonAnswer(PostGeoJson(*service_->Client(), kPost, square), 201);
  EXPECT_GT(added["tiles_updated"].get<int64_t>(), 0);
  const nlohmann::json info = Json(RunCli("tiles info " + Quote(store_) + " --surface t --json"));
  EXPECT_EQ(info["layer"]["tinbase"]["tx"], added["tx"]) << info.dump();
  const nlohmann::json changes = Json(RunCli("changes --json " + Quote(store_)));
  EXPECT_EQ(changes.back()["tx"], added["tx"]) << "the tiles made no transaction of their own";
  const int64_t id = added["features"][0].get<int64_t>();

  // A failed remove leaves the feature, its triangles and the tiles as they were.
  set_extensions("bogus");
  before_ = TableChecksums(store_);
  ExpectRefused(service_->Client()->Delete("/surfaces/t/features/" + std::to_string(id)), 400,
                "updating the tiles of the edit");
  EXPECT_EQ(Features(), 1);
  ExpectStoreChecksClean();
}

TEST_F(EditRoutesTest, BadBodiesAreRefusedNamingThePlaceAndChangeNothing) {
  Serve();
  before_ = TableChecksums(store_);
  auto client = service_->Client();
  ExpectRefused(client->Post(kPost, "{\"type\": \"Feature\",", "application/json"), 400,
                "malformed JSON: parse error at line 1, column 20");
  ExpectRefused(client->Post(kPost,
                             R"({"type": "Feature", "geometry": {"type": "LineString", )"
                             R"("coordinates": [[7.2, 43.8], [1e999, 43.9]]}})",
                             "application/json"),
                400, "malformed JSON: number overflow parsing '1e999'");
  ExpectRefused(client->Post(kPost, "[1, 2]", "application/json"), 400,
                "the body is array, not a GeoJSON Feature or FeatureCollection");
  RefuseBody({{"type", "Point"}, {"coordinates", {1, 2}}},
             "the body is a GeoJSON \"Point\"; a Feature or FeatureCollection is needed");
  RefuseBody({{"type", "FeatureCollection"}, {"features", nlohmann::json::array()}},
             "the FeatureCollection has no features");
  nlohmann::json point = LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}});
  point["geometry"] = {{"type", "Point"}, {"coordinates", {kLon, kLat}}};
  RefuseBody({{"type", "FeatureCollection"},
              {"features", {LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}}), point}}},
             "features[1]: geometry is a Point; a Polygon, MultiPolygon, LineString or "
             "MultiLineString is needed");
  nlohmann::json text_vertex = LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}});
  text_vertex["geometry"]["coordinates"][0][2] = {"7.3", 43.9};
  RefuseBody(text_vertex, "feature, ring 0, vertex 2: coordinate \"7.3\" is not a finite number");
  nlohmann::json bow_tie = LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}});
  std::swap(bow_tie["geometry"]["coordinates"][0][1], bow_tie["geometry"]["coordinates"][0][2]);
  RefuseBody(bow_tie, "feature, ring 0, vertex 0: ring crosses itself");
  RefuseBody(LonLatSquare(kLon, kLat, 0.004, {{"mode", "flood"}}),
             "feature: properties.mode: unknown feature mode 'flood'");
  RefuseBody(LonLatSquare(kLon, kLat, 0.004), "feature: a feature mode is needed");
  RefuseBody(LonLatSquare(kLon, kLat, 0.004, {{"mode", "replace"}}),
             "feature: mode replace needs a level");
  RefuseBody(LonLatSquare(kLon, kLat, 0.004, {{"mode", "breakline"}}),
             "feature: mode breakline needs a LineString or MultiLineString");
  RefuseBody(LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}, {"tag", 7}}),
             "feature: properties.tag is number, not a string");
  // Wholly off the surface: refused, as `polygon add` refuses it (one partly off is clipped).
  RefuseBody(LonLatSquare(9.5, 43.85, 0.004, {{"mode", "fill"}}),
             "feature: lies wholly outside the data area of surface 't'");
  RefuseBody(LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}}), "parameter 'crs'", "?crs=EPSG:0");
  RefuseBody(LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}}), "parameter 'level'",
             "?crs=EPSG:4326&level=nan");
}

TEST_F(EditRoutesTest, WrongContentTypesAndLargeBodiesAreRefused) {
  service::ServiceOptions options;
  options.max_body_bytes = 4096;
  Serve(options);
  before_ = TableChecksums(store_);
  const std::string body = LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}}).dump();
  ExpectRefused(service_->Client()->Post(kPost, body, "text/plain"), 415, "not 'text/plain'");
  ExpectRefused(service_->Client()->Post(kPost, body, "application/x-www-form-urlencoded"), 415,
                "application/json or application/geo+json");
  nlohmann::json large = LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}});
  large["properties"]["padding"] = std::string(8192, 'x');
  ExpectRefused(PostGeoJson(*service_->Client(), kPost, large), 413, "larger than");
  // With parameters, and the geo+json type, the same body is taken.
  JsonAnswer(service_->Client()->Post(kPost, body, "application/json; charset=utf-8"), 201);
}

TEST_F(EditRoutesTest, WritesNeedTheTokenAndAreRefusedReadOnly) {
  service::ServiceOptions options;
  options.token = "s3cret-token";
  Serve(options);
  before_ = TableChecksums(store_);
  const nlohmann::json body = LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}});
  ExpectRefused(PostGeoJson(*service_->Client(), kPost, body), 401, "needs an Authorization");
  ExpectRefused(PostGeoJson(*service_->Client(), kPost, body, "s3cret-tokem"), 401,
                "the bearer token is wrong");
  ExpectRefused(service_->Client()->Delete("/surfaces/t/features/1"), 401,
                "needs an Authorization");
  JsonAnswer(PostGeoJson(*service_->Client(), kPost, body, "s3cret-token"), 201);
  service_.reset();

  options.token.reset();
  options.read_only = true;
  Serve(options);
  before_ = TableChecksums(store_);
  ExpectRefused(PostGeoJson(*service_->Client(), kPost, body), 403, "--read-only");
  ExpectRefused(service_->Client()->Delete("/surfaces/t/features/1"), 403, "--read-only");
}

// The service's writer connection lives long; edits the CLI makes meanwhile in another process
// must be seen by its next edit, not hidden behind anything it kept.
TEST_F(EditRoutesTest, EditsInterleavedWithTheCliStayConsistent) {
  Serve();
  const nlohmann::json ours = JsonAnswer(
      PostGeoJson(*service_->Client(), kPost, LonLatSquare(kLon, kLat, 0.004, {{"mode", "fill"}})),
      201);
  const std::string square = dir_.Path("square.geojson");
  std::ofstream(square) << LonLatSquare(kLon + 0.003, kLat, 0.004).dump();
  const CliResult add =
      RunCli("polygon add " + Quote(store_) + " " + Quote(square) + " --surface t --mode erase");
  ASSERT_EQ(add.exit_code, 0) << add.err;
  const int64_t theirs = ours["features"][0].get<int64_t>() + 1;
  JsonAnswer(service_->Client()->Delete("/surfaces/t/features/" + std::to_string(theirs)));
  ExpectStoreChecksClean();
  const CliResult remove = RunCli("polygon remove " + Quote(store_) + " " +
                                  std::to_string(ours["features"][0].get<int64_t>()));
  ASSERT_EQ(remove.exit_code, 0) << remove.err;
  JsonAnswer(
      PostGeoJson(*service_->Client(), kPost, LonLatSquare(kLon, kLat, 0.002, {{"mode", "fill"}})),
      201);
  EXPECT_EQ(Features(), 1);
  ExpectStoreChecksClean();
}

// Writers of one process take turns on the writer connection: every edit of the same region
// lands, each in its own transaction, and the store checks clean.
TEST_F(EditRoutesTest, ConcurrentWritesToOneRegionAllLand) {
  Serve();
  constexpr int kWriters = 6;
  std::vector<nlohmann::json> answers(kWriters);
  std::vector<std::thread> writers;
  for (int w = 0; w < kWriters; ++w) {
    writers.emplace_back([&, w] {
      // Overlapping squares of different sizes around one point.
      const nlohmann::json body =
          LonLatSquare(kLon + 0.0005 * w, kLat, 0.002 + 0.0005 * w, {{"mode", "fill"}});
      answers[w] = JsonAnswer(PostGeoJson(*service_->Client(), kPost, body), 201);
    });
  }
  for (std::thread& t : writers) t.join();
  std::set<int64_t> txs, ids;
  for (const nlohmann::json& a : answers) {
    ASSERT_TRUE(a.is_object() && a.contains("tx")) << a.dump();
    txs.insert(a["tx"].get<int64_t>());
    ids.insert(a["features"][0].get<int64_t>());
  }
  EXPECT_EQ(txs.size(), static_cast<size_t>(kWriters));
  EXPECT_EQ(ids.size(), static_cast<size_t>(kWriters));
  EXPECT_EQ(Features(), kWriters);
  ExpectStoreChecksClean();
}

// A reader is served from its own snapshot while a writer holds the store: both this service's
// writer connection and another process's open write transaction.
TEST_F(EditRoutesTest, ReadersNeverWaitForAWriter) {
  Serve();
  auto held = service_->server().context().stores().Writer();
  ASSERT_TRUE(held.ok()) << held.status().ToString();
  auto other = Store::Open(store_);
  ASSERT_TRUE(other.ok()) << other.status().ToString();
  auto tx = (*other)->BeginWrite();
  ASSERT_TRUE(tx.ok()) << tx.status().ToString();
  Change pending;
  pending.action = "uncommitted";
  ASSERT_TRUE(AppendChange(**other, pending).ok());

  const nlohmann::json surface = JsonAnswer(service_->Client()->Get("/surfaces/t"));
  EXPECT_EQ(surface["name"], "t");
  const nlohmann::json feed = JsonAnswer(service_->Client()->Get("/changes?since=0&wait=0"));
  ASSERT_EQ(feed["changes"].size(), 1u) << "the uncommitted change is not seen: " << feed.dump();
  EXPECT_EQ(feed["changes"][0]["action"], "build");
}

}  // namespace
}  // namespace tinbase::testing
