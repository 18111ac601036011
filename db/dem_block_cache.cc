#include "db/dem_block_cache.h"

namespace tinbase {

namespace {
// Bookkeeping per entry (list node, hash node, shared_ptr control block), roughly.
constexpr size_t kEntryOverhead = 160;
}  // namespace

DemBlockCache::DemBlockCache(size_t capacity_bytes) : capacity_(capacity_bytes) {}

DemBlockCache& DemBlockCache::Instance() {
  static DemBlockCache* cache = new DemBlockCache();  // never destroyed: threads may outlive main
  return *cache;
}

size_t DemBlockCache::KeyHash::operator()(const DemBlockKey& k) const {
  // splitmix64-style mixing of the fields; the positions of neighbouring blocks differ little.
  uint64_t h = k.store;
  const auto mix = [&h](uint64_t v) {
    h ^= v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
    h ^= h >> 31;
    h *= 0xbf58476d1ce4e5b9ULL;
  };
  mix(static_cast<uint64_t>(k.dem));
  mix(static_cast<uint64_t>(k.level));
  mix(static_cast<uint64_t>(k.bx));
  mix(static_cast<uint64_t>(k.by));
  return static_cast<size_t>(h ^ (h >> 29));
}

size_t DemBlockCache::Charge(const Block& block) {
  return kEntryOverhead + (block ? block->size() * sizeof(float) : 0);
}

void DemBlockCache::SetCapacity(size_t bytes) {
  std::lock_guard lock(mu_);
  capacity_ = bytes;
  EvictTo(capacity_);
}

size_t DemBlockCache::capacity() const {
  std::lock_guard lock(mu_);
  return capacity_;
}

bool DemBlockCache::Lookup(const DemBlockKey& key, Block* block) {
  std::lock_guard lock(mu_);
  const auto it = index_.find(key);
  if (it == index_.end()) {
    ++stats_.misses;
    return false;
  }
  ++stats_.hits;
  lru_.splice(lru_.begin(), lru_, it->second);
  *block = it->second->second;
  return true;
}

void DemBlockCache::Insert(const DemBlockKey& key, Block block) {
  const size_t charge = Charge(block);
  std::lock_guard lock(mu_);
  if (const auto it = index_.find(key); it != index_.end()) {
    bytes_ -= Charge(it->second->second);
    lru_.erase(it->second);
    index_.erase(it);
  }
  if (charge > capacity_) return;
  EvictTo(capacity_ - charge);
  lru_.emplace_front(key, std::move(block));
  index_.emplace(key, lru_.begin());
  bytes_ += charge;
}

void DemBlockCache::EraseStore(uint64_t store) {
  std::lock_guard lock(mu_);
  for (auto it = lru_.begin(); it != lru_.end();) {
    if (it->first.store != store) {
      ++it;
      continue;
    }
    bytes_ -= Charge(it->second);
    index_.erase(it->first);
    it = lru_.erase(it);
  }
}

void DemBlockCache::Clear() {
  std::lock_guard lock(mu_);
  lru_.clear();
  index_.clear();
  bytes_ = 0;
}

DemBlockCache::Stats DemBlockCache::stats() const {
  std::lock_guard lock(mu_);
  Stats s = stats_;
  s.entries = index_.size();
  s.bytes = bytes_;
  return s;
}

void DemBlockCache::EvictTo(size_t bytes) {
  while (bytes_ > bytes && !lru_.empty()) {
    bytes_ -= Charge(lru_.back().second);
    index_.erase(lru_.back().first);
    lru_.pop_back();
    ++stats_.evictions;
  }
}

}  // namespace tinbase
