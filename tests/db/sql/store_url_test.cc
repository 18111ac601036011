// Store targets: which backend a text names, and the schema names that may reach SQL.
#include "db/sql/store_url.h"

#include <gtest/gtest.h>

#include "db/postgres/pg_connection.h"

namespace tinbase {
namespace {

TEST(StoreUrlTest, APathOrSqlitePrefixIsAnSqliteFile) {
  auto plain = ParseStoreUrl("maps/a.tinbase");
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(plain->backend, Backend::kSqlite);
  EXPECT_EQ(plain->sqlite_path, "maps/a.tinbase");
  auto prefixed = ParseStoreUrl("sqlite:/tmp/b.tinbase");
  ASSERT_TRUE(prefixed.ok());
  EXPECT_EQ(prefixed->sqlite_path, "/tmp/b.tinbase");
  EXPECT_FALSE(ParseStoreUrl("sqlite:").ok());
}

TEST(StoreUrlTest, APostgresUrlNamesASchemaAndHidesThePassword) {
  auto url = ParseStoreUrl("postgresql://ann:secret@db.example:5433/maps?schema=geo_1&sslmode=off");
  ASSERT_TRUE(url.ok()) << url.status().ToString();
  EXPECT_EQ(url->backend, Backend::kPostgres);
  EXPECT_EQ(url->pg_schema, "geo_1");
  EXPECT_EQ(url->pg_conninfo, "postgresql://ann:secret@db.example:5433/maps?sslmode=off");
  EXPECT_EQ(url->label.find("secret"), std::string::npos) << url->label;
  EXPECT_EQ(url->label, "postgresql://ann@db.example:5433/maps?schema=geo_1");
  auto fallback = ParseStoreUrl("postgres://h/db");
  ASSERT_TRUE(fallback.ok());
  EXPECT_EQ(fallback->pg_schema, "public");
}

TEST(StoreUrlTest, SchemaNamesThatAreNotPlainIdentifiersAreRefused) {
  for (const char* bad : {"x;DROP TABLE vertices", "Geo", "a\"b", "1abc", "", "a-b", "a b", "x'--",
                          "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"}) {
    auto url = ParseStoreUrl(std::string("postgresql://h/db?schema=") + bad);
    ASSERT_FALSE(url.ok()) << bad;
    EXPECT_EQ(url.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(url.status().message().find("is not a plain lower-case name"), std::string::npos)
        << url.status().message();
  }
}

TEST(PostgresParametersTest, QuestionMarksBecomeNumberedOutsideQuotes) {
  EXPECT_EQ(PostgresParameters("SELECT a FROM t WHERE b = ? AND c = ?"),
            "SELECT a FROM t WHERE b = $1 AND c = $2");
  EXPECT_EQ(PostgresParameters("UPDATE t SET a = ?1 WHERE id IN (?2, ?3)"),
            "UPDATE t SET a = $1 WHERE id IN ($2, $3)");
  EXPECT_EQ(PostgresParameters("SELECT '?' || ? -- why?\nFROM \"q?\""),
            "SELECT '?' || $1 -- why?\nFROM \"q?\"");
}

TEST(PostgresParametersTest, TheColumnByIsQuotedButNotTheKeyword) {
  EXPECT_EQ(PostgresParameters("SELECT bx, by FROM dem_blocks ORDER BY by, bx"),
            "SELECT bx, \"by\" FROM dem_blocks ORDER BY \"by\", bx");
  EXPECT_EQ(PostgresParameters("SELECT bypass, nearby FROM t"), "SELECT bypass, nearby FROM t");
}

}  // namespace
}  // namespace tinbase
