// WalCheckpointer: copies a store's write-ahead log back into the database file off the writer's
// commit path.
//
// SQLite's automatic checkpoint runs inside the COMMIT that crosses wal_autocheckpoint pages, so
// one insert in every few pays for writing back all the pages the others changed, and commit times
// become erratic on large stores. This replaces it: a commit that leaves kWakePages or more in the
// log wakes a background thread, which checkpoints PASSIVE (never waiting for readers or the
// writer) through its own connection. Should the log already hold kInlinePages before a commit
// adds its frames (the thread cannot keep up, or readers pin old frames), the writer checkpoints
// inline as SQLite would, so the log stays bounded (by kInlinePages plus the largest transaction).
// One big transaction alone (a bulk import of millions of rows, whose log would take long to copy
// back inside its COMMIT) only wakes the thread: the commit is as durable either way, as its
// frames are in the log. SQLite has no background checkpointer of its own; this is the pattern
// its documentation suggests for its WAL hook.
// Thread-safety: owned by the SqliteConnection whose commits it hooks (a store's writer,
// Connection::ConfigureForStore), which destroys it before closing.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "db/sqlite/sqlite_connection.h"

namespace tinbase {

class WalCheckpointer {
 public:
  static constexpr int kWakePages = 1000;
  static constexpr int kInlinePages = 65536;

  // Hooks `writer`'s commits (replacing its automatic checkpoint). The thread and its connection
  // start at the first commit that needs them.
  explicit WalCheckpointer(SqliteConnection& writer);
  ~WalCheckpointer();
  WalCheckpointer(const WalCheckpointer&) = delete;
  WalCheckpointer& operator=(const WalCheckpointer&) = delete;

  // Background checkpoints that have run so far (for tests).
  int64_t background_checkpoints() const;
  // Blocks until no wake-up is pending and no checkpoint is running (for tests).
  void WaitIdle();

 private:
  static int OnCommit(void* self, struct sqlite3* db, const char* schema, int log_pages);
  void Wake();
  void Run();
  void CheckpointOnce(SqliteConnection& connection);

  SqliteConnection& writer_;
  mutable std::mutex mu_;
  std::condition_variable wake_;
  std::condition_variable idle_;
  bool pending_ = false;
  bool running_ = false;
  bool stop_ = false;
  int64_t done_ = 0;
  int log_pages_ = 0;  // the log's length at the last commit; only OnCommit touches it
  std::thread thread_;
};

}  // namespace tinbase
