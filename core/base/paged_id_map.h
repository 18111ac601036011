// PagedIdMap: values by integer id, kept in pages of consecutive ids that are allocated on first
// use.
//
// Store row ids are dense where they are used: the builders and the update engine number rows in
// increasing order, and an edit reads them in runs (one region, one block). For such ids a lookup
// is two array indexings, where a hash map hashes, divides by a prime and chases a bucket list
// (a cache miss per lookup, on the hot path of every edit's reads).
// Memory is one page per id range in use, so ids scattered one per page cost a page each; ids past
// kMaxPages pages, and negative ids (SQLite allows them; no tinbase writer makes them), go to a
// hash map. Not thread-safe.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

namespace tinbase {

template <typename T, int kPageBits = 8>
class PagedIdMap {
 public:
  static constexpr int64_t kPageSize = int64_t{1} << kPageBits;
  static constexpr int64_t kMaxPages = int64_t{1} << 20;

  T* Find(int64_t id) { return const_cast<T*>(static_cast<const PagedIdMap&>(*this).Find(id)); }
  const T* Find(int64_t id) const {
    const int64_t page = id >> kPageBits;
    if (IsFar(page)) {
      const auto it = far_.find(id);
      return it == far_.end() ? nullptr : &it->second;
    }
    if (page >= static_cast<int64_t>(pages_.size()) || !pages_[page]) return nullptr;
    const Page& p = *pages_[page];
    const size_t slot = static_cast<size_t>(id & (kPageSize - 1));
    return p.present[slot] ? &p.values[slot] : nullptr;
  }
  bool Contains(int64_t id) const { return Find(id) != nullptr; }

  // Stores `value` under `id`, replacing any; true when `id` was absent.
  bool Put(int64_t id, T value) {
    T* slot = nullptr;
    const bool added = Slot(id, &slot);
    *slot = std::move(value);
    return added;
  }
  // The value under `id`, storing `value` there first when absent.
  T& Emplace(int64_t id, T value) {
    T* slot = nullptr;
    if (Slot(id, &slot)) *slot = std::move(value);
    return *slot;
  }
  // True when `id` was present.
  bool Erase(int64_t id) {
    const int64_t page = id >> kPageBits;
    if (IsFar(page)) {
      const bool erased = far_.erase(id) > 0;
      size_ -= erased;
      return erased;
    }
    if (page >= static_cast<int64_t>(pages_.size()) || !pages_[page]) return false;
    Page& p = *pages_[page];
    const size_t slot = static_cast<size_t>(id & (kPageSize - 1));
    if (!p.present[slot]) return false;
    p.present[slot] = false;
    p.values[slot] = T();
    --size_;
    if (--p.count == 0) {
      pages_[page].reset();
      --pages_in_use_;
    }
    return true;
  }
  void Clear() {
    pages_.clear();
    pages_in_use_ = 0;
    far_.clear();
    size_ = 0;
  }
  size_t size() const { return size_; }
  // Memory held by the values' pages and the hash map (an estimate for the latter): ids spread
  // one per page cost a whole page each, which a count of values does not show.
  size_t bytes() const {
    return pages_.capacity() * sizeof(pages_[0]) + pages_in_use_ * sizeof(Page) +
           far_.size() * (sizeof(T) + 4 * sizeof(void*));
  }

  // fn(id, value) for every stored value, pages in id order.
  template <typename Fn>
  void ForEach(Fn&& fn) const {
    for (size_t page = 0; page < pages_.size(); ++page) {
      if (!pages_[page]) continue;
      const Page& p = *pages_[page];
      for (size_t slot = 0; slot < static_cast<size_t>(kPageSize); ++slot)
        if (p.present[slot])
          fn(static_cast<int64_t>(page) * kPageSize + static_cast<int64_t>(slot), p.values[slot]);
    }
    for (const auto& [id, value] : far_) fn(id, value);
  }

 private:
  static bool IsFar(int64_t page) { return page < 0 || page >= kMaxPages; }

  struct Page {
    std::array<T, kPageSize> values{};
    std::array<bool, kPageSize> present{};
    size_t count = 0;
  };

  // Points `*slot` at the place for `id`, making it present; true when it was absent.
  bool Slot(int64_t id, T** slot) {
    const int64_t page = id >> kPageBits;
    if (IsFar(page)) {
      const auto [it, added] = far_.try_emplace(id);
      size_ += added;
      *slot = &it->second;
      return added;
    }
    if (page >= static_cast<int64_t>(pages_.size())) pages_.resize(static_cast<size_t>(page) + 1);
    if (!pages_[page]) {
      pages_[page] = std::make_unique<Page>();
      ++pages_in_use_;
    }
    Page& p = *pages_[page];
    const size_t at = static_cast<size_t>(id & (kPageSize - 1));
    *slot = &p.values[at];
    if (p.present[at]) return false;
    p.present[at] = true;
    ++p.count;
    ++size_;
    return true;
  }

  std::vector<std::unique_ptr<Page>> pages_;
  std::unordered_map<int64_t, T> far_;
  size_t size_ = 0;
  size_t pages_in_use_ = 0;
};

}  // namespace tinbase
