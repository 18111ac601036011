// A connection to PostgreSQL that drops in the middle of a write transaction leaves the store as
// it was: the server rolls the transaction back, the writer reports an error, and the store's
// rows are those of before (table checksums) and `check --full` passes. The drop is made by
// pg_terminate_backend, on the seam and on the real CLI in the middle of a polygon insert.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "db/sql/connection.h"
#include "db/sql/transaction.h"
#include "tests/db/postgres/pg_store_checksums.h"
#include "tests/support/cli_support.h"
#include "tests/support/postgres_support.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {
namespace {

std::unique_ptr<Connection> OpenStore(const std::string& target, Connection::Mode mode) {
  auto db = Connection::Open(target, mode);
  EXPECT_TRUE(db.ok()) << db.status().ToString();
  return db.ok() ? std::move(*db) : nullptr;
}

TEST(DroppedConnectionTest, TheSeamReportsTheDropAndTheServerKeepsNothing) {
  const std::string target = FreshPostgresStore("drop_seam");
  ASSERT_FALSE(target.empty());
  auto writer = OpenStore(target, Connection::Mode::kCreate);
  ASSERT_NE(writer, nullptr);
  ASSERT_TRUE(writer->Exec("CREATE TABLE t(id bigint PRIMARY KEY, v text)").ok());
  ASSERT_TRUE(writer->Exec("INSERT INTO t VALUES (1, 'kept')").ok());
  const auto before = PostgresTableChecksums(target);

  Result<int64_t> pid = writer->QueryInt("SELECT pg_backend_pid()");
  ASSERT_TRUE(pid.ok());
  {
    Result<Transaction> tx = Transaction::Begin(*writer);
    ASSERT_TRUE(tx.ok()) << tx.status().ToString();
    ASSERT_TRUE(
        writer->Exec("INSERT INTO t SELECT g, 'lost' FROM generate_series(2, 1000) g").ok());
    auto killer = OpenStore(target, Connection::Mode::kReadWrite);
    ASSERT_NE(killer, nullptr);
    Result<int64_t> killed =
        killer->QueryInt("SELECT pg_terminate_backend(" + std::to_string(*pid) + ")::int");
    ASSERT_TRUE(killed.ok()) << killed.status().ToString();
    ASSERT_EQ(*killed, 1);
    Status committed = tx->Commit();
    EXPECT_FALSE(committed.ok());
    EXPECT_EQ(committed.code(), StatusCode::kIOError) << committed.ToString();
  }
  EXPECT_EQ(PostgresTableChecksums(target), before);
}

// Waits until a backend other than `watcher`'s waits for a lock on the store's triangles table,
// and returns its pid and whether it has already written (an assigned transaction id); 0 when
// none appears within a minute.
std::pair<int64_t, bool> WaitForBlockedWriter(Connection& watcher) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(1);
  while (std::chrono::steady_clock::now() < deadline) {
    auto pid = watcher.QueryInt(
        "SELECT a.pid FROM pg_locks l JOIN pg_stat_activity a ON a.pid = l.pid "
        "WHERE NOT l.granted AND l.relation = 'triangles'::regclass LIMIT 1");
    if (pid.ok()) {
      auto wrote = watcher.QueryInt(
          "SELECT (backend_xid IS NOT NULL)::int FROM pg_stat_activity "
          "WHERE pid = " +
          std::to_string(*pid));
      return {*pid, wrote.ok() && *wrote == 1};
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return {0, false};
}

TEST(DroppedConnectionTest, APolygonInsertCutOffMidTransactionChangesNothing) {
  const std::string store = FreshPostgresStore("drop_cli");
  ASSERT_FALSE(store.empty());
  RunWrite(store, "init " + Quote(store));
  RunWrite(store,
           "dem import " + Quote(store) + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
  RunWrite(store, "tin build " + Quote(store) + " --surface terrain --tolerance 10");
  const auto before = PostgresTableChecksums(store);

  // The test holds the triangles table against writes (reads go on), so the insert stops at its
  // first triangle row with its feature rows already written; then its connection is cut.
  auto locker = OpenStore(store, Connection::Mode::kReadWrite);
  ASSERT_NE(locker, nullptr);
  ASSERT_TRUE(locker->Exec("BEGIN").ok());
  ASSERT_TRUE(locker->Exec("LOCK TABLE triangles IN EXCLUSIVE MODE").ok());
  CliResult insert;
  std::thread writer([&] {
    insert = RunCli("polygon add " + Quote(store) + " " +
                    Quote(DataPath("geology/hamersley/geology.geojson")) +
                    " --surface terrain --mode fill --tag-field unitname");
  });
  auto watcher = OpenStore(store, Connection::Mode::kReadWrite);
  const auto [pid, wrote] =
      watcher == nullptr ? std::pair<int64_t, bool>{0, false} : WaitForBlockedWriter(*watcher);
  if (pid != 0) {
    EXPECT_TRUE(wrote) << "the insert had written nothing yet when it was cut off";
    EXPECT_EQ(*watcher->QueryInt("SELECT pg_terminate_backend(" + std::to_string(pid) + ")::int"),
              1);
  }
  EXPECT_TRUE(locker->Exec("ROLLBACK").ok());
  writer.join();
  ASSERT_NE(pid, 0) << "the insert never reached the triangles table: " << insert.err;

  EXPECT_NE(insert.exit_code, 0);
  EXPECT_NE(insert.err.find("server closed the connection"), std::string::npos) << insert.err;
  EXPECT_EQ(PostgresTableChecksums(store), before);
  CliResult check = RunCli("check --full " + Quote(store));
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
}

}  // namespace
}  // namespace tinbase::testing
