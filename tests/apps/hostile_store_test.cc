// Issue 29, item 4: writing to a damaged store. A process killed with the store open leaves a
// WAL that SQLite recovers at the next open; the writer that opens it then runs quick_check and
// refuses to write to a file that fails it, naming `tinbase check` and the recovery path.
#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/cli_support.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::CliResult;
using testing::DataPath;
using testing::Quote;
using testing::RunCli;
using testing::RunWrite;
using testing::TempDir;

// Commits a change in a child process that is then killed with the store still open: the WAL
// keeps the committed frames and no process closed the store.
void CommitAndDieWithTheStoreOpen(const std::string& store) {
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    sqlite3* db = nullptr;
    if (sqlite3_open(store.c_str(), &db) != SQLITE_OK) _exit(2);
    if (sqlite3_exec(db, "INSERT INTO meta(key, value) VALUES ('killed', 'with the store open')",
                     nullptr, nullptr, nullptr) != SQLITE_OK)
      _exit(3);
    raise(SIGKILL);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << status;
  ASSERT_GT(std::filesystem::file_size(store + "-wal"), 0u);
}

// Overwrites 64 KiB in the middle of the file, as a stray write or a bad disk would.
void OverwriteTheMiddle(const std::string& store) {
  const auto size = std::filesystem::file_size(store);
  std::fstream f(store, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(static_cast<std::streamoff>(size / 2 / 4096 * 4096));
  const std::string junk(64 << 10, '\xAB');
  f.write(junk.data(), static_cast<std::streamsize>(junk.size()));
}

class HostileStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = dir_.Path("s.tinbase");
    RunWrite(store_, "init " + Quote(store_));
    RunWrite(store_,
             "dem import " + Quote(store_) + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
    RunWrite(store_, "tin build " + Quote(store_) + " --surface terrain --tolerance 10");
  }
  TempDir dir_;
  std::string store_;
};

TEST_F(HostileStoreTest, WriteAfterUncleanShutdownToADamagedStoreIsRefused) {
  CommitAndDieWithTheStoreOpen(store_);
  OverwriteTheMiddle(store_);
  const CliResult r = RunCli("polygon remove " + Quote(store_) + " 1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("was not closed cleanly and fails SQLite's quick_check"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("tinbase check --full"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST_F(HostileStoreTest, WriteAfterUncleanShutdownToASoundStoreGoesOn) {
  CommitAndDieWithTheStoreOpen(store_);
  const CliResult r = RunCli("polygon remove " + Quote(store_) + " 1");
  // No feature 1 exists: the command gets as far as looking for it.
  EXPECT_NE(r.err.find("no feature 1"), std::string::npos) << r.err;
  EXPECT_EQ(RunCli("check --full " + Quote(store_)).exit_code, 0);
}

}  // namespace
}  // namespace tinbase
