// Two edits of one PostgreSQL surface at once (docs/scaling.md, "Writers"). Edits of distant
// regions hold their region locks at the same time: each waits, holding its lock, until the other
// holds its own, which a store-wide writer lock would never let happen. Edits of overlapping
// regions serialise: the second waits on the first's lock (seen in pg_locks as a lock not yet
// granted) and, once the first commits, retries on a fresh snapshot; both land and the store
// checks clean.
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/tin/block_grid.h"
#include "db/edit/update_engine_test_hooks.h"
#include "db/polygon_editor.h"
#include "db/sql/connection.h"
#include "db/store.h"
#include "tests/support/cli_support.h"
#include "tests/support/postgres_support.h"
#include "tests/support/store_template.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {
namespace {

using std::chrono::seconds;

// A square of `side` m at (x, y) of the Hamersley DEM (EPSG:28350).
std::string Square(double x, double y, double side) {
  std::ostringstream out;
  out.precision(17);
  out << R"({"type":"FeatureCollection","crs":{"type":"name","properties":{"name":"EPSG:28350"}},)"
      << R"("features":[{"type":"Feature","properties":{},"geometry":{"type":"Polygon",)"
      << R"("coordinates":[[[)" << x << "," << y << "],[" << x + side << "," << y << "],["
      << x + side << "," << y + side << "],[" << x << "," << y + side << "],[" << x << "," << y
      << "]]]}}]}";
  return out.str();
}

class ConcurrentRegionsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = FreshPostgresStore("regions");
    ASSERT_FALSE(store_.empty());
    MakeDemStore(store_, "geology/hamersley/dtm_rp.tif");
    RunWrite(store_, "tin build " + Quote(store_) + " --surface terrain --tolerance 10");
  }

  // Adds the square in `file` as a fill tagged `tag` through a store of its own, on this thread,
  // with `on_locked` run once the edit holds its region's lock.
  Result<PolygonAddReport> Add(const std::string& file, const std::string& tag,
                               std::function<void()> on_locked) {
    UpdateEngineTestHooks hooks;
    hooks.region_locked = std::move(on_locked);
    ScopedUpdateEngineTestHooks scoped(std::move(hooks));
    TB_ASSIGN_OR_RETURN(auto store, Store::Open(store_, Store::Access::kReadWrite));
    PolygonAddOptions options;
    options.surface = "terrain";
    options.file = file;
    options.mode = FeatureMode::kFill;
    options.tag = tag;
    return AddPolygons(*store, options);
  }

  std::string WriteSquare(const std::string& name, double x, double y, double side) {
    const std::string path = dir_.Path(name);
    std::ofstream(path) << Square(x, y, side);
    return path;
  }

  int64_t Count(const std::string& sql) {
    auto db = Connection::Open(store_, Connection::Mode::kReadOnly);
    EXPECT_TRUE(db.ok()) << db.status().ToString();
    if (!db.ok()) return -1;
    auto n = (*db)->QueryInt(sql);
    EXPECT_TRUE(n.ok()) << n.status().ToString();
    return n.ok() ? *n : -1;
  }

  TempDir dir_;
  std::string store_;
};

TEST_F(ConcurrentRegionsTest, DistantEditsHoldTheirLocksAtOnce) {
  const std::string west = WriteSquare("west.geojson", 539298 - 15000, 7497339 - 5000, 1500);
  const std::string east = WriteSquare("east.geojson", 539298 + 12000, 7497339 + 5000, 1500);
  std::mutex mutex;
  std::condition_variable changed;
  int holding = 0;
  bool both_held = false;
  // Each edit, holding its lock, waits for the other to hold its own (or gives up after a time
  // long enough for any edit, so that a failure shows as a failed expectation, not a hang).
  const auto meet = [&] {
    std::unique_lock<std::mutex> lock(mutex);
    ++holding;
    changed.notify_all();
    if (changed.wait_for(lock, seconds(60), [&] { return holding == 2; })) both_held = true;
  };
  Result<PolygonAddReport> a = Status::Busy("not run"), b = Status::Busy("not run");
  std::thread first([&] { a = Add(west, "west", meet); });
  std::thread second([&] { b = Add(east, "east", meet); });
  first.join();
  second.join();
  ASSERT_TRUE(a.ok()) << a.status().ToString();
  ASSERT_TRUE(b.ok()) << b.status().ToString();
  EXPECT_TRUE(both_held) << "the two edits never held their region locks at the same time";
  EXPECT_EQ(Count("SELECT count(*) FROM features"), 2);
  CliResult check = RunCli("check --full " + Quote(store_));
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
}

TEST_F(ConcurrentRegionsTest, OverlappingEditsSerialiseAndBothLand) {
  const std::string one = WriteSquare("one.geojson", 539298 - 2000, 7497339 - 2000, 2000);
  const std::string two = WriteSquare("two.geojson", 539298 - 1000, 7497339 - 1000, 2000);
  std::mutex mutex;
  std::condition_variable changed;
  bool first_holds = false, release_first = false;
  int second_locked = 0;
  Result<PolygonAddReport> a = Status::Busy("not run"), b = Status::Busy("not run");
  std::thread first([&] {
    a = Add(one, "one", [&] {
      std::unique_lock<std::mutex> lock(mutex);
      first_holds = true;
      changed.notify_all();
      changed.wait_for(lock, seconds(60), [&] { return release_first; });
    });
  });
  {
    std::unique_lock<std::mutex> lock(mutex);
    ASSERT_TRUE(changed.wait_for(lock, seconds(120), [&] { return first_holds; }));
  }
  std::thread second([&] {
    b = Add(two, "two", [&] {
      std::lock_guard<std::mutex> lock(mutex);
      ++second_locked;
    });
  });
  // The second edit waits for a lock the first holds, and does not get past it meanwhile.
  bool waiting = false;
  for (int k = 0; k < 600 && !waiting; ++k) {
    waiting =
        Count("SELECT count(*) FROM pg_locks WHERE locktype = 'advisory' AND NOT granted") > 0;
    if (!waiting) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  {
    std::lock_guard<std::mutex> lock(mutex);
    EXPECT_TRUE(waiting) << "the second edit never waited for the first's region lock";
    EXPECT_EQ(second_locked, 0) << "the second edit held its region while the first did";
    release_first = true;
    changed.notify_all();
  }
  first.join();
  second.join();
  ASSERT_TRUE(a.ok()) << a.status().ToString();
  ASSERT_TRUE(b.ok()) << b.status().ToString();
  EXPECT_EQ(Count("SELECT count(*) FROM features"), 2);
  // The second wrote after the first committed: it found the first's rows changed and ran again.
  EXPECT_GE(second_locked, 1);
  EXPECT_GT(b->tx, a->tx);
  CliResult check = RunCli("check --full " + Quote(store_));
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
}

// More block locks than one statement's select list may hold (1664 entries) are all taken.
TEST_F(ConcurrentRegionsTest, TwoThousandBlockLocksAreAllTaken) {
  auto db = Connection::Open(store_, Connection::Mode::kReadWrite);
  ASSERT_TRUE(db.ok()) << db.status().ToString();
  ASSERT_TRUE((*db)->BeginRegionWrite().ok());
  std::vector<int64_t> blocks;
  for (int64_t by = 0; by < 40; ++by)
    for (int64_t bx = 0; bx < 50; ++bx) blocks.push_back(BlockGrid::Pack(bx, by));
  const Status locked = (*db)->LockRegion(1, blocks, false);
  EXPECT_TRUE(locked.ok()) << locked.ToString();
  // The two-number form of an advisory lock shows objsubid 2.
  auto held = (*db)->QueryInt(
      "SELECT count(*) FROM pg_locks WHERE locktype = 'advisory' AND objsubid = 2 "
      "AND pid = pg_backend_pid() AND granted");
  ASSERT_TRUE(held.ok()) << held.status().ToString();
  EXPECT_EQ(*held, 2000);
  EXPECT_TRUE((*db)->Rollback().ok());
}

}  // namespace
}  // namespace tinbase::testing
