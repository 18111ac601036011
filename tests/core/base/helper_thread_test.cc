// HelperThread: tasks run one after another on the helper, Wait returns once the last is done.
#include "core/base/helper_thread.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

namespace tinbase {
namespace {

TEST(HelperThreadTest, RunsEachTaskOnTheHelperBeforeWaitReturns) {
  HelperThread helper;
  helper.Wait();  // nothing started: returns at once
  const std::thread::id owner = std::this_thread::get_id();
  int sum = 0;
  for (int i = 1; i <= 100; ++i) {
    std::thread::id ran_on;
    helper.Run([&, i] {
      sum += i;
      ran_on = std::this_thread::get_id();
    });
    helper.Wait();
    ASSERT_NE(ran_on, owner);
  }
  EXPECT_EQ(sum, 5050);
}

// Both sides spin 50 us before they sleep: tasks given after the helper fell asleep, and tasks
// that outlast the owner's spin in Wait, take the sleeping paths.
TEST(HelperThreadTest, WakesFromSleepAndWaitsOutLongTasks) {
  HelperThread helper;
  std::atomic<int> runs{0};
  for (int i = 0; i < 5; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));  // the helper sleeps by now
    helper.Run([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));  // Wait sleeps too
      ++runs;
    });
    helper.Wait();
    ASSERT_EQ(runs.load(), i + 1);
  }
}

TEST(HelperThreadTest, DestroyedWhileIdleOrRightAfterATask) {
  { HelperThread idle; }
  int runs = 0;
  {
    HelperThread helper;
    helper.Run([&] { ++runs; });
    helper.Wait();
  }
  EXPECT_EQ(runs, 1);
}

}  // namespace
}  // namespace tinbase
