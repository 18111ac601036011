// Retrying an edit that lost a race: with concurrent writers (PostgreSQL, docs/scaling.md
// "Writers"), an edit whose rows another writer changed since its snapshot fails with Busy
// (serialisation failure, deadlock, or a lock wait past the timeout). Nothing of it was kept, so
// it runs again from the start, on a fresh snapshot, a bounded number of times with a growing
// random pause (two writers that keep colliding then stop colliding), and then fails with a
// message saying so. A single-writer store (SQLite) never retries: its Busy is the one writer's
// lock held too long, which a retry would only wait out again.
#pragma once

#include <string>

#include "core/base/status.h"
#include "db/sql/connection.h"

namespace tinbase {

inline constexpr int kMaxEditAttempts = 12;

// How many times an edit on `db` runs at most (1 when it never retries).
inline int EditAttempts(const Connection& db) {
  return db.ConcurrentWriters() ? kMaxEditAttempts : 1;
}

// Whether attempt `attempt` (from 1) of an edit that failed with `status` runs again.
inline bool RetryEdit(const Status& status, int attempt, int attempts) {
  return status.code() == StatusCode::kBusy && attempt < attempts;
}

// Sleeps before attempt `attempt` + 1: a random pause of up to 5 ms * 2^attempt, at most 0.3 s.
void PauseBeforeRetry(int attempt);

// The error of an edit that failed `attempts` times with Busy, the last time with `last`.
inline Status GaveUpRetrying(const Status& last, int attempts) {
  return Status::Busy(
      "gave up after " + std::to_string(attempts) +
      " attempts, as other writers kept changing the same region: " + last.message());
}

}  // namespace tinbase
