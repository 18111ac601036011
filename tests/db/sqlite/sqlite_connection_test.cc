// The seam of db/sql/ on its SQLite implementation: transactions roll back unless committed,
// savepoints undo only their part, snapshots stay fixed, statements are cached, and SQLite's
// errors arrive as the Status codes StatusFromSqlite promises.
#include "db/sqlite/sqlite_connection.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <fstream>
#include <string>

#include "db/sql/large_write_hint.h"
#include "db/sql/transaction.h"
#include "db/store.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

std::unique_ptr<Connection> OpenOrDie(const std::string& path, Connection::Mode mode) {
  auto db = Connection::Open(path, mode);
  EXPECT_TRUE(db.ok()) << db.status().ToString();
  return db.ok() ? std::move(*db) : nullptr;
}

// A WAL file with table t(x) holding the rows 1 and 2.
std::unique_ptr<Connection> TableOfTwo(const std::string& path) {
  auto db = OpenOrDie(path, Connection::Mode::kCreate);
  EXPECT_TRUE(db->Exec("PRAGMA journal_mode = WAL").ok());
  EXPECT_TRUE(
      db->Exec("CREATE TABLE t(x INTEGER PRIMARY KEY); INSERT INTO t VALUES (1), (2)").ok());
  return db;
}

int64_t Rows(Connection& db) { return *db.QueryInt("SELECT count(*) FROM t"); }

TEST(SqliteConnectionTest, TransactionRollsBackInItsDestructorUnlessCommitted) {
  TempDir dir;
  auto db = TableOfTwo(dir.Path("t.db"));
  {
    auto tx = Transaction::Begin(*db);
    ASSERT_TRUE(tx.ok()) << tx.status().ToString();
    EXPECT_TRUE(db->InTransaction());
    ASSERT_TRUE(db->Exec("INSERT INTO t VALUES (3)").ok());
    EXPECT_EQ(Rows(*db), 3);
  }
  EXPECT_FALSE(db->InTransaction());
  EXPECT_EQ(Rows(*db), 2);
  {
    auto tx = Transaction::Begin(*db);
    ASSERT_TRUE(tx.ok());
    ASSERT_TRUE(db->Exec("INSERT INTO t VALUES (3)").ok());
    ASSERT_TRUE(tx->Commit().ok());
    EXPECT_FALSE(db->InTransaction());
  }
  EXPECT_EQ(Rows(*db), 3);
}

TEST(SqliteConnectionTest, EarlyReturnFromAWriteLeavesNothing) {
  TempDir dir;
  auto db = TableOfTwo(dir.Path("t.db"));
  auto write = [&]() -> Status {
    TB_ASSIGN_OR_RETURN(Transaction tx, Transaction::Begin(*db));
    TB_RETURN_IF_ERROR(db->Exec("INSERT INTO t VALUES (3)"));
    TB_RETURN_IF_ERROR(db->Exec("INSERT INTO t VALUES (1)"));  // breaks the primary key
    return tx.Commit();
  };
  EXPECT_EQ(write().code(), StatusCode::kConflict);
  EXPECT_FALSE(db->InTransaction());
  EXPECT_EQ(Rows(*db), 2);
}

TEST(SqliteConnectionTest, SavepointRollsBackOnlyItsOwnPart) {
  TempDir dir;
  auto db = TableOfTwo(dir.Path("t.db"));
  auto tx = Transaction::Begin(*db);
  ASSERT_TRUE(tx.ok());
  ASSERT_TRUE(db->Exec("INSERT INTO t VALUES (3)").ok());
  {
    auto inner = Savepoint::Begin(*db, "inner");
    ASSERT_TRUE(inner.ok()) << inner.status().ToString();
    ASSERT_TRUE(db->Exec("INSERT INTO t VALUES (4)").ok());
    EXPECT_EQ(Rows(*db), 4);
  }
  EXPECT_TRUE(db->InTransaction()) << "the enclosing transaction goes on";
  EXPECT_EQ(Rows(*db), 3);
  {
    auto kept = Savepoint::Begin(*db, "kept");
    ASSERT_TRUE(kept.ok());
    ASSERT_TRUE(db->Exec("INSERT INTO t VALUES (5)").ok());
    ASSERT_TRUE(kept->Release().ok());
  }
  ASSERT_TRUE(tx->Commit().ok());
  EXPECT_EQ(Rows(*db), 4);
  EXPECT_EQ(*db->QueryInt("SELECT count(*) FROM t WHERE x = 4"), 0);
  EXPECT_EQ(*db->QueryInt("SELECT count(*) FROM t WHERE x = 5"), 1);
}

TEST(SqliteConnectionTest, SnapshotKeepsItsViewWhileAnotherConnectionCommits) {
  TempDir dir;
  const std::string path = dir.Path("t.db");
  auto writer = TableOfTwo(path);
  auto reader = OpenOrDie(path, Connection::Mode::kReadOnly);
  {
    auto snapshot = Snapshot::Begin(*reader);
    ASSERT_TRUE(snapshot.ok()) << snapshot.status().ToString();
    ASSERT_TRUE(writer->Exec("INSERT INTO t VALUES (3)").ok());
    EXPECT_EQ(Rows(*reader), 2);
  }
  EXPECT_FALSE(reader->InTransaction());
  EXPECT_EQ(Rows(*reader), 3);
}

TEST(SqliteConnectionTest, CachedStatementIsPreparedOnceAndComesBackReset) {
  TempDir dir;
  auto db = TableOfTwo(dir.Path("t.db"));
  const std::string sql = "SELECT x FROM t WHERE x >= ? ORDER BY x";
  auto first = db->Cached(sql);
  ASSERT_TRUE(first.ok());
  (*first)->Bind(1, int64_t{1});
  ASSERT_TRUE(*(*first)->Step());
  EXPECT_EQ((*first)->ColumnInt(0), 1);
  // Left in the middle of its rows: the cache hands it back reset, bindings cleared.
  auto second = db->Cached(sql);
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(*first, *second);
  EXPECT_EQ((*second)->sql(), sql);
  (*second)->Bind(1, int64_t{2});
  ASSERT_TRUE(*(*second)->Step());
  EXPECT_EQ((*second)->ColumnInt(0), 2);
  EXPECT_FALSE(*(*second)->Step());
  // A statement of its own is a different object.
  auto own = db->Prepare(sql);
  ASSERT_TRUE(own.ok());
  EXPECT_NE(own->get(), *first);
}

TEST(SqliteConnectionTest, ColumnsAndBindingsRoundTrip) {
  TempDir dir;
  auto db = OpenOrDie(dir.Path("c.db"), Connection::Mode::kCreate);
  ASSERT_TRUE(db->Exec("CREATE TABLE v(i INTEGER, d REAL, s TEXT, b BLOB, n INTEGER)").ok());
  auto insert = db->Cached("INSERT INTO v VALUES (?, ?, ?, ?, ?)");
  ASSERT_TRUE(insert.ok());
  const uint8_t blob[3] = {1, 0, 255};
  (*insert)->Bind(1, int64_t{1} << 40).Bind(2, 0.5).Bind(3, std::string_view("text"));
  (*insert)->BindBlob(4, blob, sizeof blob).BindNull(5);
  ASSERT_TRUE((*insert)->Run().ok());
  EXPECT_EQ(db->Changes(), 1);
  auto select = db->Cached("SELECT i, d, s, b, n FROM v");
  ASSERT_TRUE(select.ok());
  ASSERT_TRUE(*(*select)->Step());
  EXPECT_EQ((*select)->ColumnCount(), 5);
  EXPECT_EQ((*select)->ColumnInt(0), int64_t{1} << 40);
  EXPECT_EQ((*select)->ColumnDouble(1), 0.5);
  EXPECT_EQ((*select)->ColumnText(2), "text");
  size_t size = 0;
  const uint8_t* bytes = (*select)->ColumnBlob(3, &size);
  ASSERT_EQ(size, sizeof blob);
  EXPECT_EQ(bytes[2], 255);
  EXPECT_TRUE((*select)->ColumnIsNull(4));
  EXPECT_FALSE((*select)->ColumnIsNull(0));
  (*select)->Reset();
  EXPECT_EQ(db->QueryInt("SELECT i FROM v WHERE i < 0").status().code(), StatusCode::kNotFound);
}

TEST(SqliteConnectionTest, StoreIdentityAndSchemaVersion) {
  TempDir dir;
  auto db = OpenOrDie(dir.Path("s.db"), Connection::Mode::kCreate);
  EXPECT_EQ(*db->ApplicationId(), 0);
  EXPECT_EQ(*db->SchemaVersion(), 0);
  ASSERT_TRUE(db->SetApplicationId(kTinbaseApplicationId).ok());
  ASSERT_TRUE(db->SetSchemaVersion(7).ok());
  EXPECT_EQ(*db->ApplicationId(), kTinbaseApplicationId);
  EXPECT_EQ(*db->SchemaVersion(), 7);
}

TEST(SqliteConnectionTest, LargeWriteHintRaisesTheCacheOnlyForLargeWrites) {
  TempDir dir;
  auto db = OpenOrDie(dir.Path("h.db"), Connection::Mode::kCreate);
  const int64_t before = *db->QueryInt("PRAGMA cache_size");
  {
    LargeWriteHint small(*db, 10);
    EXPECT_FALSE(small.raised());
    LargeWriteHint large(*db, size_t{1} << 20);
    EXPECT_TRUE(large.raised());
    EXPECT_LT(*db->QueryInt("PRAGMA cache_size"), before);  // negative: KiB, larger
  }
  EXPECT_EQ(*db->QueryInt("PRAGMA cache_size"), before);
}

// --- errors ---------------------------------------------------------------------------------

TEST(SqliteConnectionTest, StatusFromSqliteMapsEveryClassOfCode) {
  EXPECT_TRUE(StatusFromSqlite(SQLITE_OK, nullptr, "x").ok());
  EXPECT_TRUE(StatusFromSqlite(SQLITE_DONE, nullptr, "x").ok());
  EXPECT_TRUE(StatusFromSqlite(SQLITE_ROW, nullptr, "x").ok());
  EXPECT_EQ(StatusFromSqlite(SQLITE_BUSY, nullptr, "x").code(), StatusCode::kBusy);
  EXPECT_EQ(StatusFromSqlite(SQLITE_BUSY_SNAPSHOT, nullptr, "x").code(), StatusCode::kBusy);
  EXPECT_EQ(StatusFromSqlite(SQLITE_LOCKED, nullptr, "x").code(), StatusCode::kBusy);
  EXPECT_EQ(StatusFromSqlite(SQLITE_CONSTRAINT_UNIQUE, nullptr, "x").code(), StatusCode::kConflict);
  EXPECT_EQ(StatusFromSqlite(SQLITE_CONSTRAINT_FOREIGNKEY, nullptr, "x").code(),
            StatusCode::kConflict);
  EXPECT_EQ(StatusFromSqlite(SQLITE_CORRUPT, nullptr, "x").code(), StatusCode::kCorruption);
  EXPECT_EQ(StatusFromSqlite(SQLITE_NOTADB, nullptr, "x").code(), StatusCode::kCorruption);
  EXPECT_EQ(StatusFromSqlite(SQLITE_NOTFOUND, nullptr, "x").code(), StatusCode::kNotFound);
  EXPECT_EQ(StatusFromSqlite(SQLITE_ERROR, nullptr, "x").code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(StatusFromSqlite(SQLITE_RANGE, nullptr, "x").code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(StatusFromSqlite(SQLITE_IOERR_WRITE, nullptr, "x").code(), StatusCode::kIOError);
  EXPECT_EQ(StatusFromSqlite(SQLITE_FULL, nullptr, "x").code(), StatusCode::kIOError);
  const Status s = StatusFromSqlite(SQLITE_CONSTRAINT, nullptr, "inserting rows");
  EXPECT_EQ(s.message().rfind("inserting rows: ", 0), 0u) << s.message();
}

TEST(SqliteConnectionTest, SecondWriterIsBusy) {
  TempDir dir;
  const std::string path = dir.Path("t.db");
  auto first = TableOfTwo(path);
  auto second = OpenOrDie(path, Connection::Mode::kReadWrite);
  ASSERT_TRUE(second->Exec("PRAGMA busy_timeout = 0").ok());
  auto tx = Transaction::Begin(*first);
  ASSERT_TRUE(tx.ok());
  auto other = Transaction::Begin(*second);
  ASSERT_FALSE(other.ok());
  EXPECT_EQ(other.status().code(), StatusCode::kBusy) << other.status().ToString();
  EXPECT_FALSE(second->InTransaction());
}

TEST(SqliteConnectionTest, BrokenConstraintIsConflictAndBadSqlIsInvalidArgument) {
  TempDir dir;
  auto db = TableOfTwo(dir.Path("t.db"));
  auto insert = db->Cached("INSERT INTO t VALUES (?)");
  ASSERT_TRUE(insert.ok());
  (*insert)->Bind(1, int64_t{2});
  EXPECT_EQ((*insert)->Run().code(), StatusCode::kConflict);
  EXPECT_EQ(db->Exec("SELEKT 1").code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(db->Prepare("SELECT nope FROM t").status().code(), StatusCode::kInvalidArgument);
}

TEST(SqliteConnectionTest, OpenSaysWhatIsWrongWithThePath) {
  TempDir dir;
  EXPECT_EQ(Connection::Open(dir.Path("none.db"), Connection::Mode::kReadOnly).status().code(),
            StatusCode::kNotFound);
  auto db = TableOfTwo(dir.Path("t.db"));
  EXPECT_EQ(Connection::Open(dir.Path("t.db"), Connection::Mode::kCreate).status().code(),
            StatusCode::kInvalidArgument);
}

TEST(SqliteConnectionTest, FileThatIsNoDatabaseIsCorruption) {
  TempDir dir;
  const std::string path = dir.Path("text.db");
  {
    std::ofstream out(path, std::ios::binary);
    for (int i = 0; i < 1000; ++i) out << "this is not a database file, only text; ";
  }
  auto db = OpenOrDie(path, Connection::Mode::kReadOnly);
  EXPECT_EQ(db->QueryInt("SELECT count(*) FROM sqlite_master").status().code(),
            StatusCode::kCorruption);
  // Store::Open tells the user what it is.
  auto store = Store::Open(path, Store::Access::kReadOnly);
  ASSERT_FALSE(store.ok());
  EXPECT_NE(store.status().message().find("not a tinbase store"), std::string::npos)
      << store.status().ToString();
}

TEST(SqliteConnectionTest, DamagedPageIsCorruption) {
  TempDir dir;
  const std::string path = dir.Path("damaged.db");
  {
    auto db = OpenOrDie(path, Connection::Mode::kCreate);
    ASSERT_TRUE(
        db->Exec("PRAGMA page_size = 4096; CREATE TABLE t(x INTEGER PRIMARY KEY, s TEXT)").ok());
    auto tx = Transaction::Begin(*db);
    ASSERT_TRUE(tx.ok());
    auto insert = db->Cached("INSERT INTO t(s) VALUES (?)");
    ASSERT_TRUE(insert.ok());
    for (int i = 0; i < 200; ++i) {
      (*insert)->Bind(1, std::string(100, 'a'));
      ASSERT_TRUE((*insert)->Run().ok());
    }
    ASSERT_TRUE(tx->Commit().ok());
  }
  {
    // Page 2 is the table's root; overwrite it with bytes no b-tree page starts with.
    std::fstream file(path, std::ios::binary | std::ios::in | std::ios::out);
    file.seekp(4096);
    const std::string garbage(4096, '\xff');
    file.write(garbage.data(), static_cast<std::streamsize>(garbage.size()));
  }
  auto db = OpenOrDie(path, Connection::Mode::kReadOnly);
  const Status s = db->QueryInt("SELECT count(*) FROM t").status();
  EXPECT_EQ(s.code(), StatusCode::kCorruption) << s.ToString();
}

}  // namespace
}  // namespace tinbase
