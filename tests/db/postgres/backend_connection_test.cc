// The seam of db/sql/connection.h behaves the same on both backends: values come back bit for bit,
// transactions and savepoints undo what they should, errors map to the same codes, and a read
// snapshot keeps its view while another connection commits.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>

#include "db/sql/connection.h"
#include "db/sql/transaction.h"
#include "tests/support/postgres_support.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

class BackendConnectionTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    target_ = GetParam() == Backend::kPostgres ? testing::FreshPostgresStore("seam")
                                               : dir_.Path("seam.db");
    ASSERT_FALSE(target_.empty());
    auto db = Connection::Open(target_, Connection::Mode::kCreate);
    ASSERT_TRUE(db.ok()) << db.status().ToString();
    db_ = std::move(*db);
    ASSERT_EQ(db_->backend(), GetParam());
    StoreSettings settings;
    settings.create = true;
    ASSERT_TRUE(db_->ConfigureForStore(settings).ok());
    const char* blob_type = GetParam() == Backend::kPostgres ? "bytea" : "BLOB";
    ASSERT_TRUE(db_->Exec(std::string("CREATE TABLE t(id bigint PRIMARY KEY, i bigint, "
                                      "d double precision, s text, b ") +
                          blob_type + ", u text UNIQUE)")
                    .ok());
  }
  std::unique_ptr<Connection> Second() {
    auto db = Connection::Open(target_, Connection::Mode::kReadWrite);
    EXPECT_TRUE(db.ok()) << db.status().ToString();
    if (!db.ok()) return nullptr;
    EXPECT_TRUE((*db)->ConfigureForStore(StoreSettings()).ok());
    return std::move(*db);
  }
  int64_t Count(Connection& db) { return *db.QueryInt("SELECT count(*) FROM t"); }

  testing::TempDir dir_;
  std::string target_;
  std::unique_ptr<Connection> db_;
};

TEST_P(BackendConnectionTest, EveryValueComesBackBitForBit) {
  std::mt19937_64 random(7);
  // Not -0.0: SQLite stores a whole REAL as an integer, and its sign with it.
  std::vector<double> doubles = {0.0,      0.1,
                                 1e300,    -1e-300,
                                 5e-324,   std::numeric_limits<double>::max(),
                                 500000.5, 4873823.944243184};
  for (int k = 0; k < 200; ++k) {
    uint64_t bits = random();
    double d;
    std::memcpy(&d, &bits, sizeof d);
    if (std::isfinite(d)) doubles.push_back(d);
  }
  const std::vector<int64_t> ints = {0, -1, std::numeric_limits<int64_t>::min(),
                                     std::numeric_limits<int64_t>::max()};
  std::string blob;
  for (int b = 0; b < 256; ++b) blob.push_back(static_cast<char>(b));
  const std::string text = "it's \"quoted\" ü 😀 ? $1 by";
  auto tx = Transaction::Begin(*db_);
  ASSERT_TRUE(tx.ok());
  auto insert = db_->Prepare("INSERT INTO t(id, i, d, s, b) VALUES (?, ?, ?, ?, ?)");
  ASSERT_TRUE(insert.ok()) << insert.status().ToString();
  for (size_t k = 0; k < doubles.size(); ++k) {
    (*insert)->Bind(1, static_cast<int64_t>(k + 1)).Bind(2, ints[k % ints.size()]);
    (*insert)->Bind(3, doubles[k]).Bind(4, text).BindBlob(5, blob.data(), blob.size());
    ASSERT_TRUE((*insert)->Run().ok());
  }
  ASSERT_TRUE(tx->Commit().ok());
  auto select = db_->Prepare("SELECT id, i, d, s, b FROM t ORDER BY id");
  ASSERT_TRUE(select.ok());
  size_t rows = 0;
  while (*(*select)->Step()) {
    const size_t k = static_cast<size_t>((*select)->ColumnInt(0) - 1);
    EXPECT_EQ((*select)->ColumnInt(1), ints[k % ints.size()]);
    const double back = (*select)->ColumnDouble(2);
    EXPECT_EQ(std::memcmp(&back, &doubles[k], sizeof back), 0)
        << doubles[k] << " came back as " << back;
    EXPECT_EQ((*select)->ColumnText(3), text);
    size_t size = 0;
    const uint8_t* bytes = (*select)->ColumnBlob(4, &size);
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(bytes), size), blob);
    ++rows;
  }
  EXPECT_EQ(rows, doubles.size());
}

TEST_P(BackendConnectionTest, NullsAndReturningIds) {
  auto insert = db_->Prepare("INSERT INTO t(id, i, s) VALUES (?, ?, ?) RETURNING id");
  ASSERT_TRUE(insert.ok());
  (*insert)->Bind(1, int64_t{41}).BindNull(2).BindNull(3);
  auto id = RunReturningId(**insert);
  ASSERT_TRUE(id.ok()) << id.status().ToString();
  EXPECT_EQ(*id, 41);
  auto select = db_->Prepare("SELECT i, s FROM t WHERE id = ?");
  (*select)->Bind(1, int64_t{41});
  ASSERT_TRUE(*(*select)->Step());
  EXPECT_TRUE((*select)->ColumnIsNull(0));
  EXPECT_TRUE((*select)->ColumnIsNull(1));
}

TEST_P(BackendConnectionTest, TransactionsAndSavepointsUndoTheirPart) {
  {
    auto tx = Transaction::Begin(*db_);
    ASSERT_TRUE(tx.ok()) << tx.status().ToString();
    ASSERT_TRUE(db_->Exec("INSERT INTO t(id) VALUES (1)").ok());
  }  // not committed
  EXPECT_EQ(Count(*db_), 0);
  {
    auto tx = Transaction::Begin(*db_);
    ASSERT_TRUE(db_->Exec("INSERT INTO t(id) VALUES (1)").ok());
    {
      auto sp = Savepoint::Begin(*db_, "part");
      ASSERT_TRUE(sp.ok()) << sp.status().ToString();
      ASSERT_TRUE(db_->Exec("INSERT INTO t(id) VALUES (2)").ok());
    }  // rolled back to the savepoint
    ASSERT_TRUE(tx->Commit().ok());
  }
  EXPECT_EQ(Count(*db_), 1);
  EXPECT_FALSE(db_->InTransaction());
}

TEST_P(BackendConnectionTest, ErrorsMapToTheSameCodes) {
  ASSERT_TRUE(db_->Exec("INSERT INTO t(id, u) VALUES (1, 'a')").ok());
  Status duplicate = db_->Exec("INSERT INTO t(id, u) VALUES (2, 'a')");
  EXPECT_EQ(duplicate.code(), StatusCode::kConflict) << duplicate.ToString();
  auto bad = db_->Prepare("SELECT nothing FROM nowhere");
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidArgument) << bad.status().ToString();
  auto none = db_->QueryInt("SELECT id FROM t WHERE id = 99");
  EXPECT_EQ(none.status().code(), StatusCode::kNotFound);
}

TEST_P(BackendConnectionTest, ASnapshotKeepsItsViewWhileAnotherCommits) {
  auto writer = Second();
  ASSERT_NE(writer, nullptr);
  {
    auto snapshot = Snapshot::Begin(*db_);
    ASSERT_TRUE(snapshot.ok()) << snapshot.status().ToString();
    EXPECT_EQ(Count(*db_), 0);
    auto tx = Transaction::Begin(*writer);
    ASSERT_TRUE(tx.ok()) << tx.status().ToString();
    ASSERT_TRUE(writer->Exec("INSERT INTO t(id) VALUES (1)").ok());
    ASSERT_TRUE(tx->Commit().ok());
    EXPECT_EQ(Count(*db_), 0) << "the snapshot saw a later commit";
  }
  EXPECT_EQ(Count(*db_), 1);
}

TEST_P(BackendConnectionTest, CreatingWhereAStoreIsIsRefusedAndOpeningNothingIsNotFound) {
  ASSERT_TRUE(db_->SetApplicationId(42).ok());
  EXPECT_EQ(*db_->ApplicationId(), 42);
  ASSERT_TRUE(db_->SetSchemaVersion(3).ok());
  EXPECT_EQ(*db_->SchemaVersion(), 3);
  auto again = Connection::Open(target_, Connection::Mode::kCreate);
  EXPECT_EQ(again.status().code(), StatusCode::kInvalidArgument) << again.status().ToString();
  const std::string absent = GetParam() == Backend::kPostgres
                                 ? testing::FreshPostgresStore("absent")
                                 : dir_.Path("absent.db");
  auto missing = Connection::Open(absent, Connection::Mode::kReadWrite);
  EXPECT_EQ(missing.status().code(), StatusCode::kNotFound) << missing.status().ToString();
}

INSTANTIATE_TEST_SUITE_P(Backends, BackendConnectionTest,
                         ::testing::Values(Backend::kSqlite, Backend::kPostgres),
                         [](const auto& info) {
                           return info.param == Backend::kPostgres ? "postgres" : "sqlite";
                         });

}  // namespace
}  // namespace tinbase
