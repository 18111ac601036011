// Migrations: the numbered, forward-only SQL files of migrations/sqlite/, compiled into tinbase.
//
// A store's schema version (Connection::SchemaVersion, in SQLite `PRAGMA user_version`) always
// equals the number of the last migration applied. The SQL is SQLite's; a second backend brings
// its own numbered list with the same numbers. The SQL text is embedded at build time
// (cmake/EmbedMigrations.cmake), so the binary needs no files at run time. Thread-safety: the list
// is immutable.
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

const std::vector<Migration>& SqliteMigrations();
int LatestSchemaVersion();

// Applies migrations (current version, target] in one transaction; nothing changes on failure.
// REQUIRES: the store's version <= target <= LatestSchemaVersion().
Status MigrateSqlite(Connection& db, int target_version);

}  // namespace tinbase
