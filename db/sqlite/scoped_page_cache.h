// ScopedPageCache: raises a connection's page cache while a large write runs, and restores it.
// SQLite's answer to Connection::BeginLargeWrite; code above the seam asks for it through
// LargeWriteHint (db/sql/large_write_hint.h).
//
// SQLite's default cache is 2 MiB. A write transaction that dirties more pages than that spills
// them into the WAL before the commit and fetches them back when it touches them again: bulk
// surface writes fill several tables and indexes at once, and the update engine repaints ~1e5
// triangles of a fill over most of a surface (their table pages, dirtied once by the repaint and
// again by the patch's rows). 64 MiB holds a few million rows' pages. A larger write gets a cache
// in proportion (kBytesPerRow a row, up to kMaxCacheKib), so a bulk write of millions of rows does
// not spill either: spilled pages are written to the log one at a time in the middle of the
// transaction, each a separate write where the commit would have written them in a run. Writes of
// fewer than kThresholdRows rows keep the connection's cache as it is; a cache set in pages
// (positive cache_size) or already larger is left alone.
// Thread-safety: as the connection; destroy it after the transaction's commit, so the commit still
// finds the dirty pages in memory.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "db/sql/connection.h"

namespace tinbase {

class ScopedPageCache final : public Connection::Scope {
 public:
  static constexpr size_t kThresholdRows = 50000;
  static constexpr int64_t kMinCacheKib = 65536;
  static constexpr int64_t kMaxCacheKib = int64_t{4} << 20;
  // A bulk-written vertex or triangle row with its index entries takes ~65 bytes of the file
  // (tin_bench delaunay: 190-202 bytes a point, one vertex and two triangle rows); the rest is
  // the cache's own header per page and pages left part full.
  static constexpr int64_t kBytesPerRow = 96;

  // The cache_size (negative: KiB) for a write of `rows` rows.
  static int64_t CacheSizeFor(size_t rows) {
    const int64_t kib = static_cast<int64_t>(rows) / 1024 * kBytesPerRow;
    return -std::clamp(kib, kMinCacheKib, kMaxCacheKib);
  }

  // `rows`: about how many rows the write inserts, updates or deletes.
  ScopedPageCache(Connection& db, size_t rows) : db_(db) {
    if (rows < kThresholdRows) return;
    const int64_t size = CacheSizeFor(rows);
    auto previous = db_.QueryInt("PRAGMA cache_size");
    if (!previous.ok() || *previous >= 0 || *previous <= size) return;
    if (db_.Exec("PRAGMA cache_size = " + std::to_string(size)).ok()) previous_ = *previous;
  }
  ~ScopedPageCache() override {
    if (previous_) (void)db_.Exec("PRAGMA cache_size = " + std::to_string(*previous_));
  }

  ScopedPageCache(const ScopedPageCache&) = delete;
  ScopedPageCache& operator=(const ScopedPageCache&) = delete;

  // True while this object holds the cache raised.
  bool raised() const { return previous_.has_value(); }

 private:
  Connection& db_;
  std::optional<int64_t> previous_;
};

}  // namespace tinbase
