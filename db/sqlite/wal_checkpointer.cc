#include "db/sqlite/wal_checkpointer.h"

#include <sqlite3.h>

namespace tinbase {

WalCheckpointer::WalCheckpointer(SqliteConnection& writer) : writer_(writer) {
  sqlite3_wal_hook(writer_.handle(), &WalCheckpointer::OnCommit, this);
}

WalCheckpointer::~WalCheckpointer() {
  sqlite3_wal_hook(writer_.handle(), nullptr, nullptr);
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

int WalCheckpointer::OnCommit(void* self, sqlite3* db, const char* schema, int log_pages) {
  auto* checkpointer = static_cast<WalCheckpointer*>(self);
  // A log shorter than at the last commit was restarted (after a full checkpoint) by this one.
  const int before = log_pages >= checkpointer->log_pages_ ? checkpointer->log_pages_ : 0;
  checkpointer->log_pages_ = log_pages;
  if (before >= kInlinePages) {
    // Errors are not the committed transaction's: it is durable in the log either way, and the
    // next commit tries again.
    sqlite3_wal_checkpoint_v2(db, schema, SQLITE_CHECKPOINT_PASSIVE, nullptr, nullptr);
  } else if (log_pages >= kWakePages) {
    checkpointer->Wake();
  }
  return SQLITE_OK;
}

void WalCheckpointer::Wake() {
  std::lock_guard<std::mutex> lock(mu_);
  pending_ = true;
  if (!thread_.joinable()) thread_ = std::thread(&WalCheckpointer::Run, this);
  wake_.notify_one();
}

void WalCheckpointer::Run() {
  auto connection = SqliteConnection::Open(writer_.path(), Connection::Mode::kReadWrite);
  std::unique_lock<std::mutex> lock(mu_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || pending_; });
    if (stop_) break;
    pending_ = false;
    running_ = true;
    lock.unlock();
    // Without a connection the log is still bounded by the writer's inline checkpoints.
    if (connection.ok()) CheckpointOnce(**connection);
    lock.lock();
    running_ = false;
    ++done_;
    idle_.notify_all();
  }
  running_ = false;
  idle_.notify_all();
}

void WalCheckpointer::CheckpointOnce(SqliteConnection& connection) {
  // A connection that has never read has not opened the log and would checkpoint nothing.
  (void)connection.QueryInt("SELECT count(*) FROM sqlite_master");
  sqlite3_wal_checkpoint_v2(connection.handle(), "main", SQLITE_CHECKPOINT_PASSIVE, nullptr,
                            nullptr);
}

int64_t WalCheckpointer::background_checkpoints() const {
  std::lock_guard<std::mutex> lock(mu_);
  return done_;
}

void WalCheckpointer::WaitIdle() {
  std::unique_lock<std::mutex> lock(mu_);
  idle_.wait(lock, [&] { return stop_ || (!pending_ && !running_); });
}

}  // namespace tinbase
