// The store a test writes to: a file in the test's temporary folder, or, when CTest runs the
// test a second time with TINBASE_TEST_BACKEND=postgresql (tests/CMakeLists.txt, "on both
// backends"), a schema of the test server that no other test uses. Tests that go through the
// storage seam or the CLI take their store from here, so one test checks both backends.
// CopyStore gives a test a private copy of a store made once (a file copy on SQLite, a schema
// copy on PostgreSQL), so a fixture that is slow to build is built once per test binary.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "db/sql/connection.h"
#include "db/sql/store_url.h"
#include "db/store.h"
#include "tests/support/postgres_support.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {

// True when this run of the test is its PostgreSQL run.
inline bool OnPostgres() {
  const char* backend = std::getenv("TINBASE_TEST_BACKEND");
  return backend != nullptr && std::string(backend) == "postgresql";
}

// The store target for `name` in `dir`: the same target each time it is asked for (a test
// creates, opens and checks one store by one name).
inline std::string StoreTarget(const TempDir& dir, const std::string& name) {
  const std::string path = dir.Path(name);
  if (!OnPostgres()) return path;
  static std::mutex mutex;
  static std::map<std::string, std::string> targets;
  std::lock_guard<std::mutex> lock(mutex);
  auto [it, fresh] = targets.try_emplace(path);
  if (fresh) it->second = FreshPostgresStore("s");
  return it->second;
}

namespace internal {

// The names of one kind of relation ('r' tables, 'S' sequences) in schema `schema`.
inline std::vector<std::string> PgRelations(Connection& db, const std::string& schema, char kind) {
  std::vector<std::string> names;
  auto query = db.Prepare(
      "SELECT c.relname FROM pg_class c JOIN pg_namespace n ON n.oid = c.relnamespace "
      "WHERE n.nspname = ? AND c.relkind::text = ? ORDER BY c.relname");
  EXPECT_TRUE(query.ok()) << query.status().ToString();
  if (!query.ok()) return names;
  (*query)->Bind(1, std::string_view(schema)).Bind(2, std::string_view(std::string(1, kind)));
  while (true) {
    auto row = (*query)->Step();
    EXPECT_TRUE(row.ok()) << row.status().ToString();
    if (!row.ok() || !*row) break;
    names.push_back((*query)->ColumnText(0));
  }
  return names;
}

// Copies every row of the store in schema `from` over the rows of the store in schema `to`
// (both made by the same migrations, so their tables and columns match), and the sequences'
// positions, in one transaction. Triggers and foreign keys are off for the copy
// (session_replication_role): the rows are a consistent store already, and the id triggers
// must keep the copied ids.
inline void CopyPgSchema(Connection& db, const std::string& from, const std::string& to) {
  auto quoted = [](const std::string& schema, const std::string& name) {
    return "\"" + schema + "\".\"" + name + "\"";
  };
  auto exec = [&db](const std::string& sql) {
    const Status s = db.Exec(sql);
    EXPECT_TRUE(s.ok()) << sql << ": " << s.ToString();
  };
  exec("BEGIN");
  exec("SET LOCAL session_replication_role = replica");
  for (const std::string& table : PgRelations(db, from, 'r')) {
    exec("DELETE FROM " + quoted(to, table));
    exec("INSERT INTO " + quoted(to, table) + " SELECT * FROM " + quoted(from, table));
  }
  for (const std::string& sequence : PgRelations(db, from, 'S')) {
    exec("SELECT setval('" + quoted(to, sequence) + "', last_value, is_called) FROM " +
         quoted(from, sequence));
  }
  exec("COMMIT");
}

}  // namespace internal

// Makes `to` (a target from StoreTarget, no store there yet) a copy of the store `from`.
inline void CopyStore(const std::string& from, const std::string& to) {
  if (!IsPostgresTarget(from)) {
    // The write-ahead log too, when a writer left one: it may hold committed pages.
    for (const char* suffix : {"", "-wal", "-shm"}) {
      if (*suffix == '\0' || std::filesystem::exists(from + suffix))
        std::filesystem::copy_file(from + suffix, to + suffix);
    }
    return;
  }
  auto source = ParseStoreUrl(from);
  auto target = ParseStoreUrl(to);
  ASSERT_TRUE(source.ok() && target.ok()) << from << " -> " << to;
  // The target's tables, views, functions and triggers come from the migrations, as any store's.
  auto created = Store::Create(to, "");
  ASSERT_TRUE(created.ok()) << created.status().ToString();
  created->reset();
  auto db = Connection::Open(to, Connection::Mode::kReadWrite);
  ASSERT_TRUE(db.ok()) << db.status().ToString();
  internal::CopyPgSchema(**db, source->pg_schema, target->pg_schema);
}

}  // namespace tinbase::testing
