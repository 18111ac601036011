// SlotHeap pops what std::priority_queue pops, in the same order, ties included: greedy
// refinement's TIN depends on that order.
#include "core/tin/slot_heap.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cstdint>
#include <queue>
#include <vector>

namespace tinbase {
namespace {

struct Keyed {
  double key;
  int64_t id;
  bool operator<(const Keyed& o) const { return key < o.key; }
};

// Pushes and pops interleaved as `ops` says (a key to push, or -1 to pop), then drains both.
std::pair<std::vector<int64_t>, std::vector<int64_t>> Popped(const std::vector<int>& ops) {
  std::priority_queue<Keyed> reference;
  SlotHeap<int64_t> heap;
  std::vector<int64_t> want, got;
  int64_t next = 0;
  const auto pop = [&] {
    want.push_back(reference.top().id);
    got.push_back(heap.top());
    EXPECT_EQ(heap.top_key(), reference.top().key);
    reference.pop();
    heap.pop();
  };
  for (int op : ops) {
    if (op >= 0) {
      reference.push(Keyed{static_cast<double>(op), next});
      heap.push(static_cast<double>(op), next);
      ++next;
    } else if (!reference.empty()) {
      pop();
    }
    EXPECT_EQ(heap.empty(), reference.empty());
  }
  while (!reference.empty()) pop();
  EXPECT_TRUE(heap.empty());
  return {want, got};
}

TEST(SlotHeapTest, TiesPopInThePriorityQueuesOrder) {
  // Few distinct keys, so most comparisons are ties.
  std::vector<int> ops;
  for (int i = 0; i < 200; ++i) ops.push_back(i % 7 == 3 ? -1 : (i * 37) % 5);
  const auto [want, got] = Popped(ops);
  EXPECT_EQ(got, want);
}

RC_GTEST_PROP(SlotHeapTest, SameOrderAsPriorityQueue, ()) {
  const auto ops = *rc::gen::container<std::vector<int>>(rc::gen::inRange(-1, 6));
  const auto [want, got] = Popped(ops);
  RC_ASSERT(got == want);
}

}  // namespace
}  // namespace tinbase
