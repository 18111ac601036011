// Readers of the change log that keep the last number they have seen, with concurrent writers
// (docs/scaling.md, "Writers"): change numbers come from a sequence and commit out of order, so
// writer A may draw N and commit after writer B drew N + 1 and committed. `tinbase changes
// --since` and `tiles update`, reading while A is still open, must not move past N: once A
// commits, the next read from where they stopped has N.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "db/change_log.h"
#include "db/sql/settled_change.h"
#include "db/sql/transaction.h"
#include "db/store.h"
#include "tests/support/cli_support.h"
#include "tests/support/postgres_support.h"
#include "tests/support/store_template.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {
namespace {

class ChangeFeedTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = FreshPostgresStore("feed");
    ASSERT_FALSE(store_.empty());
    MakeDemStore(store_, "geology/hamersley/dtm_rp.tif");
    RunWrite(store_, "tin build " + Quote(store_) + " --surface terrain --tolerance 10");
    RunWrite(store_, "tiles build " + Quote(store_) + " --surface terrain --max-zoom 11");
    auto db = Connection::Open(store_, Connection::Mode::kReadOnly);
    ASSERT_TRUE(db.ok()) << db.status().ToString();
    auto id = (*db)->QueryInt("SELECT id FROM surfaces WHERE name = 'terrain'");
    ASSERT_TRUE(id.ok()) << id.status().ToString();
    surface_ = *id;
  }

  // A writer of its own that has appended a change of 500 m square in the middle of the surface
  // and holds its transaction open; its number is `tx`.
  struct OpenWriter {
    std::unique_ptr<Store> store;
    std::unique_ptr<WriteTransaction> transaction;
    int64_t tx = 0;
  };
  OpenWriter Append() {
    OpenWriter w;
    auto store = Store::Open(store_, Store::Access::kReadWrite);
    EXPECT_TRUE(store.ok()) << store.status().ToString();
    if (!store.ok()) return w;
    w.store = std::move(*store);
    auto transaction = w.store->BeginRegionWrite();
    EXPECT_TRUE(transaction.ok()) << transaction.status().ToString();
    if (!transaction.ok()) return w;
    w.transaction = std::move(*transaction);
    Change change;
    change.surface = surface_;
    change.action = "test";
    change.min_x = 539000, change.min_y = 7497000, change.max_x = 539500, change.max_y = 7497500;
    auto tx = AppendChange(*w.store, change);
    EXPECT_TRUE(tx.ok()) << tx.status().ToString();
    if (tx.ok()) w.tx = *tx;
    return w;
  }

  // The numbers `tinbase changes --since` lists.
  std::vector<int64_t> Feed(int64_t since) {
    const nlohmann::json listed =
        Json(RunCli("changes " + Quote(store_) + " --since " + std::to_string(since) + " --json"));
    std::vector<int64_t> out;
    for (const nlohmann::json& c : listed) out.push_back(c["tx"].get<int64_t>());
    return out;
  }

  nlohmann::json TilesUpdate() {
    return Json(RunCli("tiles update " + Quote(store_) + " --surface terrain --json"));
  }

  TempDir dir_;
  std::string store_;
  int64_t surface_ = 0;
};

TEST_F(ChangeFeedTest, FeedWaitsForANumberStillInFlight) {
  const std::vector<int64_t> before = Feed(0);
  ASSERT_FALSE(before.empty());
  const int64_t start = before.back();

  OpenWriter a = Append();
  OpenWriter b = Append();
  ASSERT_GT(b.tx, a.tx);
  ASSERT_TRUE(b.transaction->Commit().ok());

  // A reader that takes the last number listed as its mark, as a client of the feed does.
  const std::vector<int64_t> first = Feed(start);
  EXPECT_TRUE(std::find(first.begin(), first.end(), b.tx) == first.end())
      << "the feed listed " << b.tx << " while " << a.tx << " below it was still in flight";
  const int64_t mark = first.empty() ? start : first.back();

  ASSERT_TRUE(a.transaction->Commit().ok());
  std::vector<int64_t> seen = first;
  const std::vector<int64_t> second = Feed(mark);
  seen.insert(seen.end(), second.begin(), second.end());
  EXPECT_NE(std::find(seen.begin(), seen.end(), a.tx), seen.end())
      << "the feed never listed " << a.tx << ", which committed after " << b.tx;
  EXPECT_NE(std::find(seen.begin(), seen.end(), b.tx), seen.end());
}

// True once a transaction of the server waits for an advisory lock, within a minute.
bool SomeoneWaitsForAnAdvisoryLock(const std::string& store) {
  auto db = Connection::Open(store, Connection::Mode::kReadOnly);
  EXPECT_TRUE(db.ok()) << db.status().ToString();
  if (!db.ok()) return false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    auto waiting = (*db)->QueryInt(
        "SELECT count(*) FROM pg_locks WHERE locktype = 'advisory' AND NOT granted "
        "AND database = (SELECT oid FROM pg_database WHERE datname = current_database())");
    if (waiting.ok() && *waiting > 0) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

TEST_F(ChangeFeedTest, TilesUpdateDoesNotSkipANumberStillInFlight) {
  OpenWriter a = Append();
  OpenWriter b = Append();
  ASSERT_GT(b.tx, a.tx);
  ASSERT_TRUE(b.transaction->Commit().ok());

  // The update reads the changes (b's; a's is not visible), then waits for the store's write
  // lock, which a holds shared until it commits: a commits while the update waits.
  nlohmann::json first;
  std::thread update([&] { first = TilesUpdate(); });
  EXPECT_TRUE(SomeoneWaitsForAnAdvisoryLock(store_));
  ASSERT_TRUE(a.transaction->Commit().ok());
  update.join();
  EXPECT_EQ(first["changes"], 1) << first.dump();  // b's, the one it sees
  EXPECT_LT(first["tx"].get<int64_t>(), a.tx)
      << "the pyramid records " << first["tx"] << ", past " << a.tx << " still in flight";

  const nlohmann::json second = TilesUpdate();
  EXPECT_GE(second["changes"].get<int64_t>(), 1)
      << "a's change, committed after b's, was never applied: " << second.dump();
  EXPECT_EQ(second["tx"], b.tx) << second.dump();
  const nlohmann::json third = TilesUpdate();
  EXPECT_EQ(third["changes"], 0) << third.dump();
}

// The horizon itself (db/sql/settled_change.h): nothing beyond what a reader sees without a gap
// while another transaction holds a number, every number drawn once none does; a region writer
// keeps the one it read before its snapshot.
TEST_F(ChangeFeedTest, SettledChangeFollowsTheWritersInFlight) {
  auto reader = Store::Open(store_, Store::Access::kReadOnly);
  ASSERT_TRUE(reader.ok()) << reader.status().ToString();
  auto last = LastTransaction(**reader);
  ASSERT_TRUE(last.ok());
  auto calm = SettledChange((*reader)->db());
  ASSERT_TRUE(calm.ok()) << calm.status().ToString();
  EXPECT_GE(*calm, *last);

  OpenWriter a = Append();
  auto during = SettledChange((*reader)->db());
  ASSERT_TRUE(during.ok());
  EXPECT_EQ(*during, 0);
  auto settled_last = SettledLastTransaction(**reader);
  ASSERT_TRUE(settled_last.ok());
  EXPECT_EQ(*settled_last, *last);
  OpenWriter b = Append();  // began while a held its number
  auto in_b = SettledChange(b.store->db());
  ASSERT_TRUE(in_b.ok());
  EXPECT_EQ(*in_b, 0);
  ASSERT_TRUE(b.transaction->Commit().ok());
  auto still = SettledLastTransaction(**reader);
  ASSERT_TRUE(still.ok());
  EXPECT_EQ(*still, *last) << "a (" << a.tx << ") is still open below b (" << b.tx << ")";

  ASSERT_TRUE(a.transaction->Commit().ok());
  auto after = SettledChange((*reader)->db());
  ASSERT_TRUE(after.ok());
  EXPECT_GE(*after, b.tx);
  auto settled_after = SettledLastTransaction(**reader);
  ASSERT_TRUE(settled_after.ok());
  EXPECT_EQ(*settled_after, b.tx);
}

}  // namespace
}  // namespace tinbase::testing
