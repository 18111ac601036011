// ScopedPageCache: raises a connection's page cache while a large write runs, and restores it.
//
// SQLite's default cache is 2 MiB. A write transaction that dirties more pages than that spills
// them into the WAL before the commit and fetches them back when it touches them again: bulk
// surface writes insert into the vertices' (surface, x, y) index in an order unrelated to ids, and
// the update engine repaints ~1e5 triangles of a fill over most of a surface (their table pages,
// dirtied once by the repaint and again by the patch's rows). 64 MiB holds a few million rows'
// pages. Writes of fewer than kThresholdRows rows keep the connection's cache as it is; a cache
// set in pages (positive cache_size) or already larger is left alone.
// Thread-safety: as the connection; destroy it after the transaction's commit, so the commit still
// finds the dirty pages in memory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "db/sqlite/sqlite_db.h"

namespace tinbase {

class ScopedPageCache {
 public:
  static constexpr size_t kThresholdRows = 50000;
  static constexpr int64_t kCacheSize = -65536;  // negative: KiB

  // `rows`: about how many rows the write inserts, updates or deletes.
  ScopedPageCache(SqliteDb& db, size_t rows) : db_(db) {
    if (rows < kThresholdRows) return;
    auto previous = db_.QueryInt("PRAGMA cache_size");
    if (!previous.ok() || *previous >= 0 || *previous <= kCacheSize) return;
    if (db_.Exec("PRAGMA cache_size = " + std::to_string(kCacheSize)).ok()) previous_ = *previous;
  }
  ~ScopedPageCache() {
    if (previous_) (void)db_.Exec("PRAGMA cache_size = " + std::to_string(*previous_));
  }

  ScopedPageCache(const ScopedPageCache&) = delete;
  ScopedPageCache& operator=(const ScopedPageCache&) = delete;

  // True while this object holds the cache raised.
  bool raised() const { return previous_.has_value(); }

 private:
  SqliteDb& db_;
  std::optional<int64_t> previous_;
};

}  // namespace tinbase
