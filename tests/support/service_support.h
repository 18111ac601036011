// Helpers for the service's tests: a store made once per ctest run and copied per test, and a
// service running on it in this process, on loopback at a free port, reached through a real
// socket with cpp-httplib's client.
#pragma once

#include <gtest/gtest.h>
#include <httplib.h>

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "service/http_server.h"
#include "tests/support/cli_support.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
#include "tests/support/store_template.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {

// The copy helpers below fail fatally (with the failed setup step's message) when the shared
// original could not be made: callers wrap them in ASSERT_NO_FATAL_FAILURE.

// A copy, at `path`, of a store holding the DEM N43E007 (SRTM, 1201 x 1201) and the surface
// "t" built on it with tolerance 20 m (DemoRecipe, made once per ctest run via the CLI).
inline void CopyDemoStore(const std::string& path) { CopyRecipeStore(DemoRecipe(), path); }

// Land of the demo store (EPSG:32632, about 7.26 E 43.9 N: ground some 550 m high) and the
// square of the fill feature CopyDemoStoreWithFeature adds there, tagged "granite".
inline constexpr double kLandX = 360000, kLandY = 4862000;
inline constexpr double kGraniteMinX = 358000, kGraniteMinY = 4860000;
inline constexpr double kGraniteMaxX = 362000, kGraniteMaxY = 4864000;

// CopyDemoStore with one fill polygon feature (the square above, attribute "unit": "u0"),
// tagged "granite". Made once per ctest run.
inline void CopyDemoStoreWithFeature(const std::string& path) {
  static const StoreRecipe recipe{
      "demo-granite", [](const std::string& store, const TempDir& scratch) {
        CopyDemoStore(store);
        const PointList square = {{kGraniteMinX, kGraniteMinY},
                                  {kGraniteMaxX, kGraniteMinY},
                                  {kGraniteMaxX, kGraniteMaxY},
                                  {kGraniteMinX, kGraniteMaxY},
                                  {kGraniteMinX, kGraniteMinY}};
        const std::string file = WritePolygons(scratch, "granite.geojson", {{square}}, 32632);
        RunWrite(store, "polygon add " + Quote(store) + " " + Quote(file) +
                            " --surface t --mode fill --tag granite");
      }};
  CopyRecipeStore(recipe, path);
}

// Where CopyDemoStoreWithTiles puts its lake, in the store's CRS (EPSG:32632, metres): a fill
// polygon of 12 sides tagged "water" around this centre.
inline constexpr double kDemoLakeX = 380000, kDemoLakeY = 4840000, kDemoLakeRadius = 3000;
// The finest level of its pyramid.
inline constexpr int kDemoTilesMaxZoom = 10;

// A copy, at `path`, of CopyDemoStore's store with the lake added and the tile pyramid of
// surface "t" built at levels 0-10 (of which 0-3 hold no tile: the surface is
// too small to show there) with every extension (octvertexnormals, watermask with water
// tag "water", metadata). The original is made once per ctest run via the CLI.
inline void CopyDemoStoreWithTiles(const std::string& path) {
  static const StoreRecipe recipe{
      "demo-tiles", [](const std::string& store, const TempDir& scratch) {
        CopyDemoStore(store);
        const std::string lake = WritePolygons(
            scratch, "lake.geojson", {{Ngon(kDemoLakeX, kDemoLakeY, kDemoLakeRadius, 12)}}, 32632);
        RunWrite(store, "polygon add " + Quote(store) + " " + Quote(lake) +
                            " --surface t --mode fill --tag water");
        RunWrite(store, "tiles build " + Quote(store) + " --surface t --max-zoom " +
                            std::to_string(kDemoTilesMaxZoom) +
                            " --extensions octvertexnormals,watermask,metadata --water-tag water");
      }};
  CopyRecipeStore(recipe, path);
}

// A service running in this process until destroyed.
class TestService {
 public:
  // Starts serving options.store_path on 127.0.0.1 at a free port (options.port is ignored).
  explicit TestService(service::ServiceOptions options) {
    options.host = "127.0.0.1";
    options.port = 0;
    auto server = service::HttpServer::Start(options);
    if (!server.ok()) {
      ADD_FAILURE() << "service did not start: " << server.status().ToString();
      return;
    }
    server_ = std::move(*server);
    thread_ = std::thread([this] { run_status_ = server_->Run(); });
  }
  ~TestService() {
    if (server_ == nullptr) return;
    server_->Stop();
    thread_.join();
    EXPECT_TRUE(run_status_.ok()) << run_status_.ToString();
  }
  TestService(const TestService&) = delete;
  TestService& operator=(const TestService&) = delete;

  bool running() const { return server_ != nullptr; }
  // 0 when the service did not start (its failure is reported): a client of it gets no answer.
  int port() const { return running() ? server_->port() : 0; }
  service::HttpServer& server() { return *server_; }
  // A client of this service with short timeouts, so a hung route fails the test.
  std::unique_ptr<httplib::Client> Client() const {
    auto client = std::make_unique<httplib::Client>("127.0.0.1", port());
    client->set_connection_timeout(5, 0);
    client->set_read_timeout(60, 0);
    return client;
  }

 private:
  std::unique_ptr<service::HttpServer> server_;
  std::thread thread_;
  Status run_status_;
};

// The JSON body of an answer that must have `status`; null JSON (and a failure) otherwise.
inline nlohmann::json JsonAnswer(const httplib::Result& r, int status = 200) {
  if (!r) {
    ADD_FAILURE() << "no answer: " << httplib::to_string(r.error());
    return nullptr;
  }
  EXPECT_EQ(r->status, status) << r->body;
  EXPECT_EQ(r->get_header_value("Content-Type"), "application/json") << r->body;
  auto j = nlohmann::json::parse(r->body, nullptr, false);
  EXPECT_FALSE(j.is_discarded()) << "not JSON: " << r->body;
  return j;
}

// Success when `j` is an object holding every one of `keys`; else a failure showing `j` (a
// failed request's error answer, say). Assert it before reading fields of a const json: reading
// a field it lacks is undefined behaviour there, and a missing value read as a number throws.
inline ::testing::AssertionResult HasFields(const nlohmann::json& j,
                                            const std::vector<std::string>& keys) {
  if (!j.is_object()) return ::testing::AssertionFailure() << "not a JSON object: " << j.dump();
  for (const std::string& key : keys)
    if (!j.contains(key))
      return ::testing::AssertionFailure() << "no field '" << key << "' in " << j.dump();
  return ::testing::AssertionSuccess();
}

// A JSON error answer with `status` whose message contains `expected`.
inline void ExpectJsonError(const httplib::Result& r, int status, const std::string& expected) {
  const nlohmann::json j = JsonAnswer(r, status);
  ASSERT_TRUE(HasFields(j, {"error"}));
  ASSERT_TRUE(HasFields(j["error"], {"status", "message"}));
  EXPECT_EQ(j["error"]["status"], status);
  const std::string message = j["error"]["message"].get<std::string>();
  EXPECT_NE(message.find(expected), std::string::npos) << message;
}

}  // namespace tinbase::testing

namespace tinbase::testing {

// A GeoJSON Feature: the square of half-side `half` degrees around (lon, lat), counter-clockwise,
// with `properties`; post it with ?crs=EPSG:4326. The demo store's land is around (7.25, 43.85).
inline nlohmann::json LonLatSquare(double lon, double lat, double half,
                                   nlohmann::json properties = nlohmann::json::object()) {
  const nlohmann::json ring = {{lon - half, lat - half},
                               {lon + half, lat - half},
                               {lon + half, lat + half},
                               {lon - half, lat + half},
                               {lon - half, lat - half}};
  return {{"type", "Feature"},
          {"properties", std::move(properties)},
          {"geometry", {{"type", "Polygon"}, {"coordinates", {ring}}}}};
}

// POSTs `body` as application/geo+json to `path` (with "Authorization: Bearer token" unless the
// token is empty).
inline httplib::Result PostGeoJson(httplib::Client& client, const std::string& path,
                                   const nlohmann::json& body, const std::string& token = "") {
  httplib::Headers headers;
  if (!token.empty()) headers.emplace("Authorization", "Bearer " + token);
  return client.Post(path, headers, body.dump(), "application/geo+json");
}

}  // namespace tinbase::testing
