// What the PostgreSQL tests compare to say "the store is unchanged": a checksum of every row of
// every table of the store's schema, by table name (the PostgreSQL side of TableChecksums in
// tests/support/test_support.h, which reads SQLite's catalog).
#pragma once

#include <map>
#include <string>

#include "db/sql/connection.h"

namespace tinbase::testing {

// The md5 of each table's rows in a fixed order, with the row count; an "<error>" entry when the
// store cannot be read.
inline std::map<std::string, std::string> PostgresTableChecksums(const std::string& store) {
  std::map<std::string, std::string> sums;
  auto db = Connection::Open(store, Connection::Mode::kReadOnly);
  if (!db.ok()) return {{"<error>", db.status().ToString()}};
  auto tables = (*db)->Prepare(
      "SELECT tablename FROM pg_tables WHERE schemaname = current_schema() ORDER BY tablename");
  if (!tables.ok()) return {{"<error>", tables.status().ToString()}};
  while (true) {
    auto row = (*tables)->Step();
    if (!row.ok() || !*row) break;
    const std::string table = (*tables)->ColumnText(0);
    auto sum = (*db)->Prepare(
        "SELECT count(*) || ' ' || coalesce(md5(string_agg(t::text, '|' "
        "ORDER BY t::text)), '') FROM \"" +
        table + "\" t");
    Result<bool> stepped = sum.ok() ? (*sum)->Step() : Result<bool>(sum.status());
    sums[table] = stepped.ok() && *stepped ? (*sum)->ColumnText(0) : "<unreadable>";
  }
  return sums;
}

}  // namespace tinbase::testing
