// DemBlockCache: the process-wide cache of decoded DEM blocks, shared by every DemStore.
//
// Decoding a block (blosc + zstd, 256 KiB for 256 x 256 cells) costs far more than sampling it, so
// decoded blocks are kept in memory across DemStores and threads, least recently used first out,
// within a memory limit in bytes (kDefaultDemBlockCacheBytes unless SetCapacity changes it).
// A key names a block of one version of one store's DEMs: DemStore stamps every store with a
// random token that each import replaces (meta key `dem_cache_token`), so blocks an import
// rewrites are never served again and the old token's entries are dropped (EraseStore). Copies of
// a store file share the token and rightly share entries. A position where no block is stored (all
// nodata) is cached too, as a null block, so sampling nodata areas does not query SQLite.
// Ownership: blocks are immutable and shared; one handed out stays valid while its holder keeps it,
// even after eviction (so the memory in use can exceed the limit by the blocks callers hold).
// Thread-safety: every member may be called from any thread; one mutex guards the LRU. DemStore
// keeps a small per-thread front cache before this one, so warm sampling takes no lock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

namespace tinbase {

inline constexpr size_t kDefaultDemBlockCacheBytes = size_t{256} << 20;

struct DemBlockKey {
  uint64_t store = 0;  // the store's current dem_cache_token
  int64_t dem = 0;
  int level = 0;
  int64_t bx = 0;
  int64_t by = 0;
  bool operator==(const DemBlockKey&) const = default;
};

class DemBlockCache {
 public:
  // Decoded cells, row-major, NaN = nodata; null: no block stored at that position.
  using Block = std::shared_ptr<const std::vector<float>>;

  struct Stats {
    int64_t hits = 0;
    int64_t misses = 0;
    int64_t evictions = 0;
    size_t entries = 0;
    size_t bytes = 0;  // charged bytes held, <= capacity
  };

  explicit DemBlockCache(size_t capacity_bytes = kDefaultDemBlockCacheBytes);
  DemBlockCache(const DemBlockCache&) = delete;
  DemBlockCache& operator=(const DemBlockCache&) = delete;

  // The one cache of the process.
  static DemBlockCache& Instance();

  // Sets the memory limit and evicts down to it. 0 disables caching (Insert keeps nothing).
  void SetCapacity(size_t bytes);
  size_t capacity() const;

  // True with *block set (possibly null: nothing stored there) when the key is cached; marks it
  // most recently used. False on a miss.
  bool Lookup(const DemBlockKey& key, Block* block);
  // Caches `block` (null allowed) under `key`, replacing any entry, and evicts least recently
  // used entries beyond the limit. A block larger than the whole limit is not kept.
  void Insert(const DemBlockKey& key, Block block);
  // Drops every entry of the store token `store`.
  void EraseStore(uint64_t store);
  void Clear();
  Stats stats() const;

  // What an entry is charged: its cells plus bookkeeping.
  static size_t Charge(const Block& block);

 private:
  struct KeyHash {
    size_t operator()(const DemBlockKey& k) const;
  };
  using Entry = std::pair<DemBlockKey, Block>;

  void EvictTo(size_t bytes);  // REQUIRES: mu_ held

  mutable std::mutex mu_;
  size_t capacity_;
  size_t bytes_ = 0;
  std::list<Entry> lru_;  // most recently used first
  std::unordered_map<DemBlockKey, std::list<Entry>::iterator, KeyHash> index_;
  Stats stats_;
};

}  // namespace tinbase
