#include "db/migrations.h"

#include "db/migrations_embedded.h"
#include "db/sql/transaction.h"

namespace tinbase {

namespace {

template <typename Embedded>
std::vector<Migration> ListOf(const Embedded& embedded) {
  std::vector<Migration> list;
  for (const auto& m : embedded) list.push_back({m.version, m.name, m.sql});
  return list;
}

static_assert(kEmbeddedSqliteMigrations.size() == kEmbeddedPostgresqlMigrations.size(),
              "every migration needs its SQLite and its PostgreSQL form");

}  // namespace

const std::vector<Migration>& MigrationsFor(Backend backend) {
  static const std::vector<Migration> sqlite = ListOf(kEmbeddedSqliteMigrations);
  static const std::vector<Migration> postgresql = ListOf(kEmbeddedPostgresqlMigrations);
  return backend == Backend::kPostgres ? postgresql : sqlite;
}

int LatestSchemaVersion() { return static_cast<int>(kEmbeddedSqliteMigrations.size()); }

Status MigrateStore(Connection& db, int target_version) {
  TB_ASSIGN_OR_RETURN(int64_t current, db.SchemaVersion());
  if (target_version < current || target_version > LatestSchemaVersion())
    return Status::InvalidArgument("cannot migrate schema from version " + std::to_string(current) +
                                   " to " + std::to_string(target_version));
  if (current == target_version) return Status::Ok();
  TB_ASSIGN_OR_RETURN(Transaction tx, Transaction::Begin(db));
  for (const Migration& m : MigrationsFor(db.backend())) {
    if (m.version <= current || m.version > target_version) continue;
    TB_RETURN_IF_ERROR(db.Exec(m.sql).WithContext("migration " + m.name));
  }
  TB_RETURN_IF_ERROR(db.SetSchemaVersion(target_version));
  return tx.Commit();
}

}  // namespace tinbase
