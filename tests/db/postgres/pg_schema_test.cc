// The PostgreSQL migrations produce exactly schema/postgresql.sql, as the SQLite ones produce
// schema/sqlite.sql; a PostgreSQL store opens, refuses and reports as an SQLite one does.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <set>
#include <sstream>

#include "db/migrations.h"
#include "db/sql/connection.h"
#include "db/store.h"
#include "tests/support/postgres_support.h"

namespace tinbase {
namespace {

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Every catalog row that describes the schema of `db` (its search_path's first), with the
// schema's own name taken out of the texts, so two schemas compare.
std::set<std::string> SchemaOf(Connection& db) {
  const char* queries[] = {
      "SELECT 'column ' || table_name || '.' || column_name || ' ' || data_type || ' ' || "
      "is_nullable || ' ' || coalesce(column_default, '-') || ' ' || ordinal_position "
      "FROM information_schema.columns WHERE table_schema = current_schema()",
      "SELECT 'constraint ' || c.conrelid::regclass::text || ' ' || c.conname || ' ' || "
      "pg_get_constraintdef(c.oid) FROM pg_constraint c JOIN pg_namespace n ON n.oid = "
      "c.connamespace WHERE n.nspname = current_schema()",
      "SELECT 'index ' || indexname || ' ' || replace(indexdef, current_schema() || '.', '') "
      "FROM pg_indexes WHERE schemaname = current_schema()",
      "SELECT 'view ' || viewname || ' ' || definition FROM pg_views "
      "WHERE schemaname = current_schema()",
      "SELECT 'trigger ' || t.tgname || ' ' || replace(pg_get_triggerdef(t.oid), "
      "current_schema() || '.', '') FROM pg_trigger t JOIN pg_class c ON c.oid = t.tgrelid "
      "JOIN pg_namespace n ON n.oid = c.relnamespace WHERE n.nspname = current_schema() "
      "AND NOT t.tgisinternal",
      "SELECT 'function ' || p.proname || ' ' || p.prosrc FROM pg_proc p JOIN pg_namespace n "
      "ON n.oid = p.pronamespace WHERE n.nspname = current_schema()"};
  std::set<std::string> rows;
  for (const char* sql : queries) {
    auto stmt = db.Prepare(sql);
    EXPECT_TRUE(stmt.ok()) << stmt.status().ToString();
    if (!stmt.ok()) continue;
    while (*(*stmt)->Step()) rows.insert((*stmt)->ColumnText(0));
  }
  return rows;
}

TEST(PgSchemaTest, MigrationsProduceExactlyTheSchemaFile) {
  const std::string target = testing::FreshPostgresStore("migrated");
  const std::string reference_target = testing::FreshPostgresStore("reference");
  ASSERT_FALSE(target.empty());
  auto store = Store::Create(target, "");
  ASSERT_TRUE(store.ok()) << store.status().ToString();
  EXPECT_EQ((*store)->SchemaVersion(), LatestSchemaVersion());
  auto reference = Connection::Open(reference_target, Connection::Mode::kCreate);
  ASSERT_TRUE(reference.ok()) << reference.status().ToString();
  Status loaded = (*reference)->Exec(ReadFile(std::string(TINBASE_SCHEMA_DIR) + "/postgresql.sql"));
  ASSERT_TRUE(loaded.ok()) << loaded.ToString();
  const std::set<std::string> migrated = SchemaOf((*store)->db());
  const std::set<std::string> expected = SchemaOf(**reference);
  EXPECT_GT(migrated.size(), 100u);
  for (const std::string& row : migrated)
    EXPECT_TRUE(expected.count(row)) << "only the migrations make: " << row;
  for (const std::string& row : expected)
    EXPECT_TRUE(migrated.count(row)) << "only schema/postgresql.sql makes: " << row;
}

TEST(PgSchemaTest, BothBackendsHaveEveryMigration) {
  const auto& sqlite = MigrationsFor(Backend::kSqlite);
  const auto& postgresql = MigrationsFor(Backend::kPostgres);
  ASSERT_EQ(sqlite.size(), postgresql.size());
  for (size_t i = 0; i < sqlite.size(); ++i) {
    EXPECT_EQ(postgresql[i].version, static_cast<int>(i + 1));
    EXPECT_EQ(postgresql[i].name, sqlite[i].name) << "the same step has the same name";
  }
}

TEST(PgSchemaTest, ASchemaThatIsNotAStoreIsRefused) {
  const std::string target = testing::FreshPostgresStore("other");
  ASSERT_FALSE(target.empty());
  {
    auto db = Connection::Open(target, Connection::Mode::kCreate);
    ASSERT_TRUE(db.ok());
    ASSERT_TRUE((*db)->Exec("CREATE TABLE wells(id bigint, depth double precision)").ok());
  }
  auto store = Store::Open(target);
  ASSERT_FALSE(store.ok());
  EXPECT_NE(store.status().message().find("is not a tinbase store"), std::string::npos)
      << store.status().message();
}

// A database without PostGIS: the store can neither be made nor opened, and the message says what
// to install. An unknown user cannot connect, and the message says so.
TEST(PgSchemaTest, ADatabaseWithoutPostgisOrAnUnknownUserIsNamed) {
  const std::string url = testing::PostgresUrl();
  ASSERT_FALSE(url.empty());
  const std::string server = url.substr(0, url.rfind('/'));
  const std::string database = "nopostgis_" + std::to_string(getpid());
  {
    auto admin = Connection::Open(server + "/postgres", Connection::Mode::kReadWrite);
    ASSERT_TRUE(admin.ok()) << admin.status().ToString();
    ASSERT_TRUE((*admin)->Exec("CREATE DATABASE " + database).ok());
  }
  const std::string target = server + "/" + database + "?schema=maps";
  auto store = Store::Create(target, "");
  ASSERT_FALSE(store.ok());
  EXPECT_NE(store.status().message().find("PostGIS is not installed in this database"),
            std::string::npos)
      << store.status().message();
  auto left = Store::Open(target);
  EXPECT_FALSE(left.ok()) << "a failed create left a store that opens";

  const std::string stranger = "postgresql://nobody_here@" + url.substr(url.find('@') + 1);
  auto refused = Connection::Open(stranger, Connection::Mode::kReadWrite);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), StatusCode::kIOError);
  EXPECT_NE(refused.status().message().find("cannot connect"), std::string::npos)
      << refused.status().message();
  EXPECT_NE(refused.status().message().find("nobody_here"), std::string::npos)
      << refused.status().message();
}

}  // namespace
}  // namespace tinbase
