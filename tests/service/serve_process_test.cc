// The real `tinbase serve` process killed with SIGKILL while clients post edits: the store it
// leaves passes `check --full`, and every edit the service answered 201 is in it (SQLite's WAL
// makes a commit durable before the answer goes out). Two rounds, the second on the store the
// first kill left, with tiles, so a kill can land in an edit or in the tile update after it.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "db/feature_store.h"
#include "db/surface_store.h"
#include "tests/support/serve_child.h"
#include "tests/support/service_support.h"
#include "tests/support/store_target.h"

namespace tinbase::testing {
namespace {

using testing::ServeChild;

// Clients posting small squares at distinct places until the service goes away; what they were
// answered 201 is collected.
class Posters {
 public:
  Posters(int port, int clients, int round) {
    for (int c = 0; c < clients; ++c) {
      threads_.emplace_back([this, port, c, round] {
        httplib::Client client("127.0.0.1", port);
        client.set_read_timeout(60, 0);
        for (int k = 0;; ++k) {
          const double lon = 7.05 + 0.012 * k, lat = 43.70 + 0.03 * c + 0.012 * round;
          auto r = PostGeoJson(client, "/surfaces/t/features?crs=EPSG:4326",
                               LonLatSquare(lon, lat, 0.003, {{"mode", "fill"}}));
          if (!r || r->status != 201) {
            std::lock_guard<std::mutex> lock(mutex_);
            if (r) refused_.push_back(r->body);  // the service answered, so it was not the kill
            ++stopped_;
            changed_.notify_all();
            return;
          }
          const auto answer = nlohmann::json::parse(r->body);
          std::lock_guard<std::mutex> lock(mutex_);
          for (const auto& id : answer["features"]) acknowledged_.push_back(id.get<int64_t>());
          changed_.notify_all();
        }
      });
    }
  }
  ~Posters() {
    for (std::thread& t : threads_) t.join();
  }
  // Until `n` edits were answered, or every client stopped.
  void WaitFor(size_t n) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return acknowledged_.size() >= n || stopped_ == threads_.size(); });
  }
  std::vector<std::string> Refused() {
    std::lock_guard<std::mutex> lock(mutex_);
    return refused_;
  }
  std::vector<int64_t> Acknowledged() {
    std::lock_guard<std::mutex> lock(mutex_);
    return acknowledged_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<int64_t> acknowledged_;
  std::vector<std::string> refused_;
  size_t stopped_ = 0;
  std::vector<std::thread> threads_;
};

TEST(ServeProcessTest, KillDuringWritesLeavesAStoreThatChecksClean) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "s.tinbase");
  CopyDemoStore(store);
  RunWrite(store, "tiles build " + Quote(store) + " --surface t --max-zoom 9");
  std::vector<int64_t> acknowledged;
  for (int round = 0; round < 2; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    ServeChild serve(store);
    ASSERT_GT(serve.port(), 0);
    {
      Posters posters(serve.port(), 3, round);
      posters.WaitFor(4);
      serve.Kill();  // the posters' next requests fail, and they stop
      const std::vector<int64_t> ids = posters.Acknowledged();
      EXPECT_GE(ids.size(), 4u);
      for (const std::string& body : posters.Refused()) ADD_FAILURE() << "refused: " << body;
      acknowledged.insert(acknowledged.end(), ids.begin(), ids.end());
    }
    const CliResult check = RunCli("check --full " + Quote(store));
    EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  }
  // Every answered edit survived the kills.
  auto opened = Store::Open(store, Store::Access::kReadOnly);
  ASSERT_TRUE(opened.ok()) << opened.status().ToString();
  auto surface = SurfaceStore(**opened).Find("t");
  ASSERT_TRUE(surface.ok());
  for (int64_t id : acknowledged)
    EXPECT_TRUE(LoadFeature(**opened, *surface, id).ok()) << "feature " << id << " was lost";
  // And the store goes on: the tiles catch up with whatever the last kill interrupted.
  RunWrite(store, "tiles update " + Quote(store) + " --surface t");
}

}  // namespace
}  // namespace tinbase::testing
