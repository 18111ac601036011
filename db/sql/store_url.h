// StoreUrl: which backend and which database a store target names, parsed once for every caller
// (CLI, server, tests).
//
//   PATH or sqlite:PATH                       an SQLite file
//   postgresql://[user[:password]@]host[:port]/db[?schema=NAME&...]   (or postgres://)
//                                             a PostgreSQL schema (default "public"); the other
//                                             parameters go to libpq as they are
// The schema must be a plain lower-case identifier ([a-z_][a-z0-9_]*, at most 63 bytes): it is
// written into SQL, so nothing else may pass. Thread-safety: plain values.
#pragma once

#include <string>

#include "core/base/status.h"
#include "db/sql/connection.h"

namespace tinbase {

struct StoreUrl {
  Backend backend = Backend::kSqlite;
  std::string sqlite_path;  // kSqlite
  std::string pg_conninfo;  // kPostgres: the URI for libpq, without schema=
  std::string pg_schema;    // kPostgres
  std::string label;        // for messages: the target without its password
};

// InvalidArgument naming the target and the problem (an empty path, a bad schema name).
Result<StoreUrl> ParseStoreUrl(const std::string& target);

// Whether `target` names a PostgreSQL store (it begins with postgresql:// or postgres://).
bool IsPostgresTarget(const std::string& target);

}  // namespace tinbase
