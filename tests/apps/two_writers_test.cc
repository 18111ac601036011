// Two writers on one store for a minute (docs/reliability.md, "Two writers"): `tinbase serve`
// answering clients that post features, and the CLI adding polygons one command after another.
// SQLite lets one of them write at a time; the other waits up to the busy timeout. Each write
// must either land (201, exit 0) or be refused with a clear `busy` error (503 with code "busy";
// exit 1 with one line naming it). Afterwards nothing acknowledged is lost, nothing refused is
// there, and the store passes `check --full`.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <iostream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "db/feature_store.h"
#include "db/surface_store.h"
#include "tests/support/cli_support.h"
#include "tests/support/serve_child.h"
#include "tests/support/service_support.h"
#include "tests/support/store_target.h"

namespace tinbase::testing {
namespace {

constexpr auto kDuration = std::chrono::seconds(60);

// What one writer saw.
struct Tally {
  std::vector<int64_t> features;  // acknowledged (the service's ids)
  int64_t landed = 0;
  int64_t busy = 0;
};

// Posts squares over the south of the demo store (each its own place) until `stop`.
Tally PostUntil(int port, const std::atomic<bool>& stop) {
  Tally tally;
  httplib::Client client("127.0.0.1", port);
  client.set_read_timeout(60, 0);
  for (int k = 0; !stop; ++k) {
    const double lon = 7.05 + 0.012 * (k % 60), lat = 43.70 + 0.012 * (k / 60 % 5);
    auto r = PostGeoJson(client, "/surfaces/t/features?crs=EPSG:4326",
                         LonLatSquare(lon, lat, 0.003, {{"mode", "fill"}}));
    if (!r) {
      ADD_FAILURE() << "no answer from the service: " << httplib::to_string(r.error());
      break;
    }
    if (r->status == 201) {
      ++tally.landed;
      const auto answer = nlohmann::json::parse(r->body);
      for (const auto& id : answer["features"]) tally.features.push_back(id.get<int64_t>());
      continue;
    }
    ++tally.busy;
    EXPECT_EQ(r->status, 503) << r->body;
    const auto error = nlohmann::json::parse(r->body, nullptr, false);
    EXPECT_EQ(error.is_object() ? error.value("/error/code"_json_pointer, "") : "", "busy")
        << r->body;
  }
  return tally;
}

// Adds squares with the CLI, one command each, over the north of the demo store until the time
// is up.
Tally AddWithCliFor(const TempDir& dir, const std::string& store) {
  Tally tally;
  const auto end = std::chrono::steady_clock::now() + kDuration;
  for (int k = 0; std::chrono::steady_clock::now() < end; ++k) {
    const double x = 350000 + 700.0 * (k % 20), y = 4860000 + 700.0 * (k / 20 % 10);
    const PointList square = {{x, y}, {x + 300, y}, {x + 300, y + 300}, {x, y + 300}, {x, y}};
    const std::string file = WritePolygons(dir, "cli.geojson", {{square}}, 32632);
    const CliResult r = RunCli("polygon add " + Quote(store) + " " + Quote(file) +
                               " --surface t --mode fill --tag cli");
    if (r.exit_code == 0) {
      ++tally.landed;
      continue;
    }
    ++tally.busy;
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("busy"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line expected: " << r.err;
  }
  return tally;
}

int64_t FeatureCount(const std::string& store, const std::string& where) {
  auto opened = Store::Open(store, Store::Access::kReadOnly);
  EXPECT_TRUE(opened.ok()) << opened.status().ToString();
  if (!opened.ok()) return -1;
  auto n = (*opened)->db().QueryInt("SELECT count(*) FROM features WHERE " + where);
  EXPECT_TRUE(n.ok()) << n.status().ToString();
  return n.ok() ? *n : -1;
}

TEST(TwoWritersTest, ServeAndCliWriteOneStoreForAMinute) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "s.tinbase");
  CopyDemoStore(store);
  Tally served, cli;
  {
    ServeChild serve(store);
    ASSERT_GT(serve.port(), 0);
    std::atomic<bool> stop{false};
    std::thread poster([&] { served = PostUntil(serve.port(), stop); });
    cli = AddWithCliFor(dir, store);
    stop = true;
    poster.join();
  }
  std::cout << "service: " << served.landed << " landed, " << served.busy
            << " busy; CLI: " << cli.landed << " landed, " << cli.busy << " busy\n";
  // Both wrote: neither starved the other for the whole minute.
  EXPECT_GT(served.landed, 0);
  EXPECT_GT(cli.landed, 0);
  const CliResult check = RunCli("check --full " + Quote(store));
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  // Nothing acknowledged is lost and nothing refused landed.
  EXPECT_EQ(
      FeatureCount(store, "tag IS NULL OR tag NOT IN (SELECT id FROM tags WHERE value = 'cli')"),
      static_cast<int64_t>(served.features.size()));
  EXPECT_EQ(FeatureCount(store, "tag IN (SELECT id FROM tags WHERE value = 'cli')"), cli.landed);
  auto opened = Store::Open(store, Store::Access::kReadOnly);
  ASSERT_TRUE(opened.ok()) << opened.status().ToString();
  auto surface = SurfaceStore(**opened).Find("t");
  ASSERT_TRUE(surface.ok());
  for (int64_t id : served.features)
    EXPECT_TRUE(LoadFeature(**opened, *surface, id).ok()) << "feature " << id << " was lost";
}

}  // namespace
}  // namespace tinbase::testing
