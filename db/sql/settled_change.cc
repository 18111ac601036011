// SettledChange of settled_change.h: the one place above a backend's connection that asks which
// backend it is, as the answer needs the PostgreSQL connection's state (what it read before its
// transaction's snapshot was taken).
#include "db/sql/settled_change.h"

#include <limits>

#include "db/postgres/pg_connection.h"

namespace tinbase {

Result<int64_t> SettledChange(Connection& db) {
  if (db.backend() != Backend::kPostgres) return std::numeric_limits<int64_t>::max();
  if (auto* pg = dynamic_cast<PgConnection*>(&db)) return pg->SettledChange();
  return 0;
}

}  // namespace tinbase
