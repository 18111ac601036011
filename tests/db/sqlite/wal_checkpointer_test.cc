// The checkpointer moves a large log into the database file in the background, and leaves small
// commits alone.
#include "db/sqlite/wal_checkpointer.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

std::unique_ptr<SqliteConnection> WalDb(const std::string& path) {
  auto db = SqliteConnection::Open(path, SqliteConnection::Mode::kCreate);
  EXPECT_TRUE(db.ok()) << db.status().ToString();
  EXPECT_TRUE((*db)->Exec("PRAGMA journal_mode = WAL").ok());
  EXPECT_TRUE((*db)->Exec("CREATE TABLE blobs(id INTEGER PRIMARY KEY, data BLOB)").ok());
  return std::move(*db);
}

// One transaction of `count` 4 KiB blobs: about one log page each.
void InsertBlobs(SqliteConnection& db, int count) {
  ASSERT_TRUE(db.Exec("BEGIN IMMEDIATE").ok());
  auto insert = db.Cached("INSERT INTO blobs(data) VALUES (?)");
  ASSERT_TRUE(insert.ok());
  const std::vector<uint8_t> data(4000, 7);
  for (int i = 0; i < count; ++i)
    ASSERT_TRUE((*insert)->BindBlob(1, data.data(), data.size()).Run().ok());
  ASSERT_TRUE(db.Exec("COMMIT").ok());
}

TEST(WalCheckpointer, CopiesALargeLogIntoTheDatabaseFileInTheBackground) {
  TempDir dir;
  const std::string path = dir.Path("big.db");
  auto db = WalDb(path);
  const auto size_before = std::filesystem::file_size(path);
  WalCheckpointer checkpointer(*db);
  InsertBlobs(*db, 2 * WalCheckpointer::kWakePages);
  checkpointer.WaitIdle();
  EXPECT_EQ(checkpointer.background_checkpoints(), 1);
  // Only a checkpoint writes the pages into the main file; the commit put them in the log.
  EXPECT_GT(std::filesystem::file_size(path), size_before + 2 * WalCheckpointer::kWakePages * 4000);
  // The writer goes on, and its rows are all there.
  InsertBlobs(*db, 10);
  auto rows = db->QueryInt("SELECT count(*) FROM blobs");
  ASSERT_TRUE(rows.ok());
  EXPECT_EQ(*rows, 2 * WalCheckpointer::kWakePages + 10);
}

// One transaction longer than kInlinePages (a bulk import) does not pay for the copy inside its
// COMMIT: the log was short before it, so the thread does the copy.
TEST(WalCheckpointer, OneBigCommitIsCopiedInTheBackground) {
  TempDir dir;
  const std::string path = dir.Path("bulk.db");
  auto db = WalDb(path);
  const auto size_before = std::filesystem::file_size(path);
  WalCheckpointer checkpointer(*db);
  InsertBlobs(*db, WalCheckpointer::kInlinePages + 100);
  checkpointer.WaitIdle();
  EXPECT_EQ(checkpointer.background_checkpoints(), 1);
  EXPECT_GT(std::filesystem::file_size(path),
            size_before + uintmax_t{WalCheckpointer::kInlinePages} * 4000);
}

TEST(WalCheckpointer, LeavesSmallCommitsInTheLog) {
  TempDir dir;
  const std::string path = dir.Path("small.db");
  auto db = WalDb(path);
  const auto size_before = std::filesystem::file_size(path);
  WalCheckpointer checkpointer(*db);
  for (int i = 0; i < 5; ++i) InsertBlobs(*db, 20);
  checkpointer.WaitIdle();
  EXPECT_EQ(checkpointer.background_checkpoints(), 0);
  EXPECT_EQ(std::filesystem::file_size(path), size_before);
}

}  // namespace
}  // namespace tinbase
