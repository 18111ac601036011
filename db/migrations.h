// Migrations: the numbered, forward-only SQL files of migrations/sqlite/ and
// migrations/postgresql/, compiled into tinbase.
//
// A store's schema version (Connection::SchemaVersion: in SQLite `PRAGMA user_version`, in
// PostgreSQL the tinbase_store table) always equals the number of the last migration applied.
// Each backend has its own list, with the same numbers and the same tables, columns, keys and
// checks after each number (tests/db/migrations_test.cc compares each list with its schema/ file).
// The SQL text is embedded at build time (cmake/EmbedMigrations.cmake), so the binary needs no
// files at run time. Thread-safety: the lists are immutable.
#pragma once

#include <string>
#include <vector>

#include "core/base/status.h"
#include "db/sql/connection.h"

namespace tinbase {

struct Migration {
  int version;       // 1, 2, ... in order, no gaps
  std::string name;  // file name, e.g. "0001_dems.sql"
  std::string sql;
};

const std::vector<Migration>& MigrationsFor(Backend backend);
inline const std::vector<Migration>& SqliteMigrations() { return MigrationsFor(Backend::kSqlite); }
int LatestSchemaVersion();

// Applies the migrations of db's backend in (current version, target] in one transaction;
// nothing changes on failure. REQUIRES: the store's version <= target <= LatestSchemaVersion().
Status MigrateStore(Connection& db, int target_version);

}  // namespace tinbase
