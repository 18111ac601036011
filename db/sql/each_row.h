// EachRow: the loop every query that reads many rows writes: step, hand each row over, and reset
// the statement whether the rows ran out or a step failed, so a cached statement is ready for
// its next use either way.
// Thread-safety: as the Statement's (one thread at a time).
#pragma once

#include <utility>

#include "core/base/status.h"
#include "db/sql/connection.h"

namespace tinbase {

// Calls `fn(stmt)` for every row `stmt` returns (its parameters bound), then resets `stmt`.
// Returns OK when the rows ran out, else the first failed step's status (rows before it were
// handed over). `fn` returns nothing; it reads the row's columns and must not step or reset.
template <typename Fn>
Status EachRow(Statement& stmt, Fn&& fn) {
  for (;;) {
    Result<bool> row = stmt.Step();
    if (!row.ok() || !*row) {
      stmt.Reset();
      return row.ok() ? Status::Ok() : row.status();
    }
    std::forward<Fn>(fn)(stmt);
  }
}

}  // namespace tinbase
