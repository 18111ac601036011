// SqliteConnection's journals through SQLite's own VFS: in WAL mode every committed byte is with
// the OS when COMMIT returns (another connection sees each commit at once, a process killed right
// after its commits loses none of them), a transaction that spilled frames and rolled back leaves
// the log consistent, and a statement journal larger than SqliteConnection keeps in memory spills
// to a file.
#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>

#include "db/sqlite/sqlite_connection.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

constexpr int kRowsPerCommit = 40;  // of ~1 KiB: about ten pages a commit

std::unique_ptr<SqliteConnection> OpenLog(const std::string& path, SqliteConnection::Mode mode) {
  auto db = SqliteConnection::Open(path, mode);
  EXPECT_TRUE(db.ok()) << db.status().ToString();
  EXPECT_TRUE((*db)->Exec("PRAGMA journal_mode = WAL").ok());
  EXPECT_TRUE((*db)->Exec("PRAGMA synchronous = NORMAL").ok());
  EXPECT_TRUE((*db)->Exec("PRAGMA wal_autocheckpoint = 0").ok());  // frames stay in the log
  return std::move(*db);
}

// A new database at `path` with the table the tests fill.
std::unique_ptr<SqliteConnection> NewTable(const std::string& path) {
  auto db = OpenLog(path, SqliteConnection::Mode::kCreate);
  EXPECT_TRUE(db->Exec("CREATE TABLE t(tx INTEGER, payload BLOB)").ok());
  return db;
}

Status CommitRows(SqliteConnection& db, int commit) {
  TB_RETURN_IF_ERROR(db.Exec("BEGIN"));
  for (int r = 0; r < kRowsPerCommit; ++r)
    TB_RETURN_IF_ERROR(db.Exec("INSERT INTO t(tx, payload) VALUES (" + std::to_string(commit) +
                               ", randomblob(1000))"));
  return db.Exec("COMMIT");
}

// A connection of SQLite's own, which sees only what reached the file.
class PlainReader {
 public:
  explicit PlainReader(const std::string& path) {
    EXPECT_EQ(sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  }
  ~PlainReader() { sqlite3_close(db_); }
  int64_t Int(const std::string& sql) {
    return Row(sql, [](sqlite3_stmt* stmt) { return sqlite3_column_int64(stmt, 0); });
  }
  std::string Text(const std::string& sql) {
    return Row(sql, [](sqlite3_stmt* stmt) {
      return std::string(reinterpret_cast<const char*>(sqlite3_column_text(stmt, 0)));
    });
  }

 private:
  // The first column of the first row of `sql`, read by `column`.
  template <typename Column>
  auto Row(const std::string& sql, Column column) -> decltype(column(nullptr)) {
    sqlite3_stmt* stmt = nullptr;
    EXPECT_EQ(sqlite3_prepare_v2(db_, sql.c_str(), -1, &stmt, nullptr), SQLITE_OK);
    EXPECT_EQ(sqlite3_step(stmt), SQLITE_ROW) << sqlite3_errmsg(db_);
    auto value = column(stmt);
    sqlite3_finalize(stmt);
    return value;
  }

  sqlite3* db_ = nullptr;
};

TEST(SqliteDbJournalTest, AnotherConnectionSeesEachCommitAtOnce) {
  TempDir dir;
  const std::string path = dir.Path("a.db");
  auto db = NewTable(path);
  PlainReader reader(path);
  for (int commit = 1; commit <= 20; ++commit) {
    ASSERT_TRUE(CommitRows(*db, commit).ok());
    ASSERT_EQ(reader.Int("SELECT count(*) FROM t"), commit * kRowsPerCommit) << commit;
    ASSERT_EQ(reader.Int("SELECT max(tx) FROM t"), commit);
  }
  EXPECT_EQ(reader.Text("PRAGMA integrity_check"), "ok");
}

TEST(SqliteDbJournalTest, AProcessKilledAfterItsCommitsLosesNone) {
  TempDir dir;
  const std::string path = dir.Path("a.db");
  NewTable(path);  // closed again: the child opens its own connection
  constexpr int kCommits = 25;
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    auto db = OpenLog(path, SqliteConnection::Mode::kReadWrite);
    for (int commit = 1; commit <= kCommits; ++commit)
      if (!CommitRows(*db, commit).ok()) _exit(1);
    // Nothing closes the connection or flushes anything more.
    raise(SIGKILL);
    _exit(2);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << status;
  PlainReader reader(path);
  EXPECT_EQ(reader.Int("SELECT count(*) FROM t"), kCommits * kRowsPerCommit);
  EXPECT_EQ(reader.Int("SELECT count(DISTINCT tx) FROM t"), kCommits);
  EXPECT_EQ(reader.Text("PRAGMA integrity_check"), "ok");
}

TEST(SqliteDbJournalTest, SpilledFramesOfARolledBackTransactionLeaveTheLogConsistent) {
  TempDir dir;
  const std::string path = dir.Path("a.db");
  auto db = NewTable(path);
  ASSERT_TRUE(db->Exec("PRAGMA cache_size = 8").ok());  // a transaction spills frames early
  ASSERT_TRUE(CommitRows(*db, 1).ok());
  for (int round = 0; round < 3; ++round) {
    ASSERT_TRUE(db->Exec("BEGIN").ok());
    for (int r = 0; r < 20 * kRowsPerCommit; ++r)
      ASSERT_TRUE(db->Exec("INSERT INTO t(tx, payload) VALUES (99, randomblob(1000))").ok());
    ASSERT_TRUE(db->Exec("ROLLBACK").ok());
    ASSERT_TRUE(CommitRows(*db, 2 + round).ok());
  }
  // A spilling transaction that commits: its early frames were gathered or written before.
  ASSERT_TRUE(db->Exec("BEGIN").ok());
  for (int r = 0; r < 20 * kRowsPerCommit; ++r)
    ASSERT_TRUE(db->Exec("INSERT INTO t(tx, payload) VALUES (7, randomblob(1000))").ok());
  ASSERT_TRUE(db->Exec("COMMIT").ok());
  PlainReader reader(path);
  EXPECT_EQ(reader.Int("SELECT count(*) FROM t WHERE tx = 99"), 0);
  EXPECT_EQ(reader.Int("SELECT count(*) FROM t WHERE tx = 7"), 20 * kRowsPerCommit);
  EXPECT_EQ(reader.Int("SELECT count(*) FROM t"), 4 * kRowsPerCommit + 20 * kRowsPerCommit);
  EXPECT_EQ(reader.Text("PRAGMA integrity_check"), "ok");
  db.reset();  // the last connection checkpoints the log into the file
  PlainReader after(path);
  EXPECT_EQ(after.Int("SELECT count(*) FROM t"), 24 * kRowsPerCommit);
}

// A statement journal far larger than what SqliteConnection keeps in memory spills to a temporary
// file without failing: SQLite writes the spill one in-memory chunk a call, and the unix VFS would
// write at most 128 KiB - 1 bytes of a larger chunk and report a full disk.
TEST(SqliteDbJournalTest, AStatementJournalLargerThanTheInMemoryLimitSpills) {
  TempDir dir;
  auto db = SqliteConnection::Open(dir.Path("j.db"), SqliteConnection::Mode::kCreate);
  ASSERT_TRUE(db.ok()) << db.status().ToString();
  SqliteConnection& d = **db;
  ASSERT_TRUE(d.Exec("PRAGMA journal_mode = WAL").ok());
  // A CHECK makes every UPDATE one that may fail part way, so it keeps a statement journal.
  ASSERT_TRUE(
      d.Exec("CREATE TABLE t(id INTEGER PRIMARY KEY, n INTEGER CHECK (n >= 0), b BLOB)").ok());
  ASSERT_TRUE(d.Exec("WITH RECURSIVE k(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM k WHERE "
                     "i < 60000) INSERT INTO t SELECT i, 0, randomblob(400) FROM k")
                  .ok());  // ~26 MB of pages
  ASSERT_TRUE(d.Exec("BEGIN").ok());
  // The first statement changes every page; the second must journal every one of them again.
  const Status first = d.Exec("UPDATE t SET n = n + 1");
  ASSERT_TRUE(first.ok()) << first.ToString();
  const Status second = d.Exec("UPDATE t SET n = n + 1");
  EXPECT_TRUE(second.ok()) << second.ToString();
  ASSERT_TRUE(d.Exec("COMMIT").ok());
  auto sum = d.QueryInt("SELECT sum(n) FROM t");
  ASSERT_TRUE(sum.ok());
  EXPECT_EQ(*sum, 120000);
}

}  // namespace
}  // namespace tinbase
