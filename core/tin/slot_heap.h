// SlotHeap: a max-priority queue by a double key whose heap holds only (key, slot) pairs, the
// payloads kept aside in slots that are reused once popped.
//
// Greedy refinement (core/tin/tolerance_refiner.cc) queues a candidate per scanned face, millions
// on a dense TIN, and most of its queue time is the cache misses of sifting: 16-byte entries put
// four children to a cache line where its 40-byte candidates put one and a half. The heap is
// reordered by std::push_heap and std::pop_heap on the key alone, as std::priority_queue does
// on a payload compared by the same key: the same comparisons give the same order, ties
// included, so a queue of either kind pops the same payloads in the same order.
// Thread-safety: none (one owner).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace tinbase {

template <typename T>
class SlotHeap {
 public:
  bool empty() const { return heap_.empty(); }
  // REQUIRES: !empty().
  double top_key() const { return heap_.front().key; }
  const T& top() const { return slots_[heap_.front().slot]; }

  void push(double key, const T& value) {
    uint64_t slot = 0;
    if (free_.empty()) {
      slot = slots_.size();
      slots_.push_back(value);
    } else {
      slot = free_.back();
      free_.pop_back();
      slots_[slot] = value;
    }
    heap_.push_back(Entry{key, slot});
    std::push_heap(heap_.begin(), heap_.end());
  }

  // REQUIRES: !empty().
  void pop() {
    std::pop_heap(heap_.begin(), heap_.end());
    free_.push_back(heap_.back().slot);
    heap_.pop_back();
  }

 private:
  struct Entry {
    double key;
    uint64_t slot;
    bool operator<(const Entry& o) const { return key < o.key; }
  };
  std::vector<Entry> heap_;
  std::vector<T> slots_;
  std::vector<uint64_t> free_;
};

}  // namespace tinbase
