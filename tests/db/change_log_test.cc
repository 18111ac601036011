// The change log read by readers that keep the last number they have seen (db/change_log.h): how
// far such a reader may move its mark past numbers it does not see, and that with no writer in
// flight a rolled-back number holds nobody back, on both backends. What a writer still in flight
// does to them is in tests/db/postgres/change_feed_test.cc.
#include "db/change_log.h"

#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "db/sql/settled_change.h"
#include "db/sql/transaction.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

std::vector<Change> Numbered(const std::vector<int64_t>& numbers) {
  std::vector<Change> out;
  for (int64_t tx : numbers) {
    Change c;
    c.tx = tx;
    out.push_back(c);
  }
  return out;
}

TEST(SettledThroughTest, StopsBeforeTheFirstUnseenNumberThatMayStillCommit) {
  const std::vector<Change> seen = Numbered({6, 7, 9, 10, 13});
  EXPECT_EQ(SettledThrough(5, seen, 0), 7);  // 8 may still commit
  EXPECT_EQ(SettledThrough(5, seen, 7), 7);
  EXPECT_EQ(SettledThrough(5, seen, 8), 10);  // 8 was rolled back; 11 may still commit
  EXPECT_EQ(SettledThrough(5, seen, 12), 13);
  EXPECT_EQ(SettledThrough(4, seen, 4), 4);  // 5 may still commit
  EXPECT_EQ(SettledThrough(5, {}, 0), 5);
  EXPECT_EQ(SettledThrough(5, seen, std::numeric_limits<int64_t>::max()), 13);
}

class ChangeLogTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = Store::Create(testing::StoreTarget(dir_, "s.tinbase"), "EPSG:32632");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
  }

  // Appends one change in a write transaction of its own, committed or rolled back.
  int64_t Append(bool commit) {
    auto tx = store_->BeginWrite();
    EXPECT_TRUE(tx.ok()) << tx.status().ToString();
    if (!tx.ok()) return 0;
    Change change;
    change.action = commit ? "kept" : "rolled back";
    auto number = AppendChange(*store_, change);
    EXPECT_TRUE(number.ok()) << number.status().ToString();
    if (commit) {
      EXPECT_TRUE((*tx)->Commit().ok());
    }
    return number.ok() ? *number : 0;
  }

  testing::TempDir dir_;
  std::unique_ptr<Store> store_;
};

TEST_F(ChangeLogTest, WithNoWriterInFlightEveryCommittedChangeIsSettled) {
  const int64_t first = Append(true);
  Append(false);
  const int64_t second = Append(true);
  const int64_t third = Append(true);
  auto settled = SettledChange(store_->db());
  ASSERT_TRUE(settled.ok()) << settled.status().ToString();
  EXPECT_GE(*settled, third);

  auto all = SettledChangesSince(*store_, 0);
  ASSERT_TRUE(all.ok()) << all.status().ToString();
  std::vector<int64_t> numbers;
  for (const Change& c : *all) numbers.push_back(c.tx);
  EXPECT_EQ(numbers, (std::vector<int64_t>{first, second, third}));
  for (const Change& c : *all) EXPECT_EQ(c.action, "kept");

  auto after_first = SettledChangesSince(*store_, first);
  ASSERT_TRUE(after_first.ok());
  ASSERT_EQ(after_first->size(), 2u);
  EXPECT_EQ(after_first->front().tx, second);

  auto last = SettledLastTransaction(*store_);
  ASSERT_TRUE(last.ok()) << last.status().ToString();
  EXPECT_EQ(*last, third);
}

TEST_F(ChangeLogTest, AnEmptyLogIsSettledAtZero) {
  auto last = SettledLastTransaction(*store_);
  ASSERT_TRUE(last.ok()) << last.status().ToString();
  EXPECT_EQ(*last, 0);
  auto none = SettledChangesSince(*store_, 0);
  ASSERT_TRUE(none.ok());
  EXPECT_TRUE(none->empty());
}

}  // namespace
}  // namespace tinbase
