// SettledChange: how far a reader of the change log may trust what it sees (docs/scaling.md,
// "Writers"). With concurrent writers (PostgreSQL) change numbers commit out of order, so a
// reader that keeps the last number it has seen must not move past a number it has not seen
// that may still commit (db/change_log.h SettledThrough).
#pragma once

#include <cstdint>

#include "core/base/status.h"
#include "db/sql/connection.h"

namespace tinbase {

// A change number (`changes.tx`) at or below which every change that will ever commit is seen by
// `db`'s reads: by its open transaction's snapshot, else by the statements after this call. A
// number at most this that a read does not see was rolled back; a larger one may still commit,
// below numbers the read sees. A backend with one writer, which commits its numbers in order
// (SQLite): the largest int64. PostgreSQL: PgConnection::SettledChange; another connection to it
// (the extension's, inside the server): 0, nothing beyond what is seen without a gap.
Result<int64_t> SettledChange(Connection& db);

}  // namespace tinbase
