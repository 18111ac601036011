// LargeWriteHint: tells the connection that a write of about `rows` rows follows, for as long as
// the hint lives (Connection::BeginLargeWrite).
//
// SQLite raises its page cache so a large transaction does not spill dirty pages into its log
// before the commit (db/sqlite/scoped_page_cache.h); a backend with nothing to tune ignores it.
// Destroy the hint after the transaction's commit, so the commit still finds its pages in memory.
// Thread-safety: as the connection.
#pragma once

#include <cstddef>
#include <memory>

#include "db/sql/connection.h"

namespace tinbase {

class LargeWriteHint {
 public:
  // `rows`: about how many rows the write inserts, updates or deletes.
  LargeWriteHint(Connection& db, size_t rows) : scope_(db.BeginLargeWrite(rows)) {}
  LargeWriteHint(const LargeWriteHint&) = delete;
  LargeWriteHint& operator=(const LargeWriteHint&) = delete;

  // True while the backend holds something changed for the write (a larger hint then changes
  // nothing more).
  bool raised() const { return scope_ != nullptr; }

 private:
  std::unique_ptr<Connection::Scope> scope_;
};

}  // namespace tinbase
