#include "db/migrations.h"

#include "db/migrations_embedded.h"
#include "db/sql/transaction.h"

namespace tinbase {

const std::vector<Migration>& SqliteMigrations() {
  static const std::vector<Migration> migrations = [] {
    std::vector<Migration> list;
    for (const auto& m : kEmbeddedSqliteMigrations) list.push_back({m.version, m.name, m.sql});
    return list;
  }();
  return migrations;
}

int LatestSchemaVersion() { return static_cast<int>(SqliteMigrations().size()); }

Status MigrateSqlite(Connection& db, int target_version) {
  TB_ASSIGN_OR_RETURN(int64_t current, db.SchemaVersion());
  if (target_version < current || target_version > LatestSchemaVersion())
    return Status::InvalidArgument("cannot migrate schema from version " + std::to_string(current) +
                                   " to " + std::to_string(target_version));
  if (current == target_version) return Status::Ok();
  TB_ASSIGN_OR_RETURN(Transaction tx, Transaction::Begin(db));
  for (const Migration& m : SqliteMigrations()) {
    if (m.version <= current || m.version > target_version) continue;
    TB_RETURN_IF_ERROR(db.Exec(m.sql).WithContext("migration " + m.name));
  }
  TB_RETURN_IF_ERROR(db.SetSchemaVersion(target_version));
  return tx.Commit();
}

}  // namespace tinbase
