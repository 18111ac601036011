// Bulk writes reach every row once, in order, whatever the count (full batches, then halving
// ones), inserts number rows as NextId said, a statement over ids changes only those rows, and a
// statement that fails part way is undone alone.
#include "db/sql/bulk_write.h"

#include <gtest/gtest.h>

#include <string>

#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

std::unique_ptr<Connection> Table(const TempDir& dir) {
  auto db = Connection::Open(dir.Path("bulk.db"), Connection::Mode::kCreate);
  EXPECT_TRUE(db.ok()) << db.status().ToString();
  EXPECT_TRUE((*db)
                  ->Exec("CREATE TABLE t(id INTEGER PRIMARY KEY, a INTEGER NOT NULL, "
                         "b TEXT NOT NULL CHECK (b <> 'bad'))")
                  .ok());
  return std::move(*db);
}

// Rows in id order as "a:b".
std::vector<std::string> Rows(Connection& db) {
  auto stmt = db.Cached("SELECT a, b FROM t ORDER BY id");
  EXPECT_TRUE(stmt.ok());
  std::vector<std::string> rows;
  while (*(*stmt)->Step())
    rows.push_back(std::to_string((*stmt)->ColumnInt(0)) + ":" + (*stmt)->ColumnText(1));
  (*stmt)->Reset();
  return rows;
}

TEST(BulkWriteTest, EveryCountWritesEachRowOnceInOrder) {
  for (size_t count : {0, 1, 2, 3, 31, 32, 33, 63, 64, 65, 127, 128, 200, 255}) {
    TempDir dir;
    auto db = Table(dir);
    ASSERT_TRUE(db->Exec("BEGIN").ok());
    const int64_t first = *NextId(*db, "t", count);
    ASSERT_TRUE(InsertNumberedRows(*db, "t(a, b)", 2, count, first,
                                   [](Statement& row, int p, size_t r) {
                                     row.Bind(p, static_cast<int64_t>(r));
                                     row.Bind(p + 1, "row" + std::to_string(r));
                                   })
                    .ok())
        << count;
    ASSERT_TRUE(db->Exec("COMMIT").ok());
    const std::vector<std::string> rows = Rows(*db);
    ASSERT_EQ(rows.size(), count);
    for (size_t r = 0; r < count; ++r) {
      EXPECT_EQ(rows[r], std::to_string(r) + ":row" + std::to_string(r)) << count;
    }
    if (count > 0) {
      EXPECT_EQ(*db->QueryInt("SELECT max(id) FROM t"), first + int64_t(count) - 1);
    }
  }
}

TEST(BulkWriteTest, ABadRowFailsTheInsertWithSQLitesMessage) {
  TempDir dir;
  auto db = Table(dir);
  ASSERT_TRUE(db->Exec("BEGIN").ok());
  const Status status = InsertRows(*db, "t(a, b)", 2, 100, [](Statement& row, int p, size_t r) {
    row.Bind(p, static_cast<int64_t>(r));
    row.Bind(p + 1, r == 90 ? "bad" : "good");
  });
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("CHECK"), std::string::npos) << status.ToString();
  ASSERT_TRUE(db->Exec("ROLLBACK").ok());
  EXPECT_TRUE(Rows(*db).empty());
}

TEST(BulkWriteTest, RunOverIdsReachesEveryIdOnce) {
  for (size_t count : {0, 1, 37, 64, 100}) {
    TempDir dir;
    auto db = Table(dir);
    ASSERT_TRUE(InsertRows(*db, "t(a, b)", 2, 200, [](Statement& row, int p, size_t r) {
                  row.Bind(p, static_cast<int64_t>(r));
                  row.Bind(p + 1, "old");
                }).ok());
    std::vector<int64_t> ids;  // every other id from 2 on, descending
    for (size_t r = count; r > 0; --r) ids.push_back(static_cast<int64_t>(2 * r));
    int64_t changes = 0;
    ASSERT_TRUE(RunOverIds(
                    *db, "UPDATE t SET b = ?1, a = -id WHERE id IN", " AND b IS NOT ?1", 1, ids,
                    [](Statement& stmt) { stmt.Bind(1, "new"); }, &changes)
                    .ok());
    EXPECT_EQ(changes, static_cast<int64_t>(count));
    const std::vector<std::string> rows = Rows(*db);
    ASSERT_EQ(rows.size(), 200u);
    for (size_t r = 0; r < rows.size(); ++r) {
      const auto id = static_cast<int64_t>(r + 1);
      const bool updated = id % 2 == 0 && id <= static_cast<int64_t>(2 * count);
      EXPECT_EQ(rows[r], updated ? std::to_string(-id) + ":new" : std::to_string(r) + ":old")
          << count << " ids, row " << id;
    }
  }
}

// A multi-row statement that breaks a foreign key after a statement of more than 64 KiB of pages
// (SQLite's default point to spill its statement journal to a file; tinbase keeps it in memory)
// is undone alone: the rows of the earlier statements stay.
TEST(BulkWriteTest, AFailedStatementIsUndoneAloneAfterALargeOne) {
  TempDir dir;
  auto db = Connection::Open(dir.Path("fk.db"), Connection::Mode::kCreate);
  ASSERT_TRUE(db.ok());
  ASSERT_TRUE((*db)->Exec("PRAGMA foreign_keys = ON").ok());
  ASSERT_TRUE((*db)
                  ->Exec("CREATE TABLE parent(id INTEGER PRIMARY KEY); INSERT INTO parent "
                         "VALUES (1); CREATE TABLE child(id INTEGER PRIMARY KEY, p INTEGER "
                         "REFERENCES parent(id), blob TEXT)")
                  .ok());
  const std::string big(3000, 'x');
  ASSERT_TRUE((*db)->Exec("BEGIN").ok());
  const auto insert = [&](size_t rows, size_t orphan) {
    std::string sql = "INSERT INTO child(p, blob) VALUES ";
    for (size_t r = 0; r < rows; ++r)
      sql += std::string(r ? ", " : "") + "(" + (r == orphan ? "2" : "1") + ", '" + big + "')";
    return (*db)->Exec(sql);
  };
  ASSERT_TRUE(insert(64, 64).ok());  // ~190 KiB of pages, all valid
  EXPECT_FALSE(insert(64, 63).ok());
  ASSERT_TRUE((*db)->Exec("COMMIT").ok());
  EXPECT_EQ(*(*db)->QueryInt("SELECT count(*) FROM child"), 64);
  EXPECT_EQ(*(*db)->QueryInt("SELECT count(*) FROM child WHERE p NOT IN (SELECT id FROM parent)"),
            0);
}

}  // namespace
}  // namespace tinbase
