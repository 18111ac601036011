// SqliteConnection and SqliteStatement: the SQLite backend of the seam in db/sql/connection.h, a
// thin RAII layer over the SQLite C API.
//
// All SQLite result codes become Status values in exactly one function, StatusFromSqlite(), so no
// code sees an `int rc`. A connection owns its cache of prepared statements and, once configured
// as a store's writer, the WalCheckpointer that hooks its commits. Nothing outside db/sqlite/
// names these classes except Connection::Open (db/sql/connection.cc) and the tests of this
// folder. Thread-safety: a connection and its statements belong to one thread at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>

#include "core/base/status.h"
#include "db/sql/connection.h"

struct sqlite3;
struct sqlite3_stmt;

namespace tinbase {

class WalCheckpointer;

// Maps an SQLite result code (and the connection's message) to a Status: BUSY and LOCKED ->
// Busy, CONSTRAINT -> Conflict, CORRUPT and NOTADB -> Corruption, NOTFOUND -> NotFound, misuse of
// SQL (ERROR, MISMATCH, RANGE, TOOBIG) -> InvalidArgument, everything else -> IOError. `context`
// says what was being done ("inserting triangles").
Status StatusFromSqlite(int rc, sqlite3* db, std::string_view context);

class SqliteStatement final : public Statement {
 public:
  SqliteStatement(sqlite3* db, sqlite3_stmt* stmt, std::string sql);
  ~SqliteStatement() override;

  SqliteStatement& Bind(int index, int64_t value) override;
  SqliteStatement& Bind(int index, double value) override;
  SqliteStatement& Bind(int index, std::string_view text) override;
  SqliteStatement& BindStaticText(int index, const char* text) override;
  SqliteStatement& BindBlob(int index, const void* data, size_t size) override;
  SqliteStatement& BindNull(int index) override;

  Result<bool> Step() override;
  Status Run() override;
  void Reset() override;

  int ColumnCount() const override;
  int64_t ColumnInt(int index) const override;
  double ColumnDouble(int index) const override;
  std::string ColumnText(int index) const override;
  bool ColumnIsNull(int index) const override;
  const uint8_t* ColumnBlob(int index, size_t* size) const override;

 private:
  sqlite3* db_;
  sqlite3_stmt* stmt_;
};

class SqliteConnection final : public Connection {
 public:
  // Opens the SQLite file `path` (Connection::Open's contract), through the WAL write-batching
  // VFS, with extended result codes and a busy timeout.
  static Result<std::unique_ptr<SqliteConnection>> Open(const std::string& path, Mode mode);
  ~SqliteConnection() override;

  Status Exec(std::string_view sql) override;
  Result<std::unique_ptr<Statement>> Prepare(std::string_view sql) override;
  Result<Statement*> Cached(std::string_view sql) override;

  int64_t Changes() const override;
  int64_t TotalChanges() const override;
  // PRAGMA data_version.
  Result<int64_t> DataVersion() override;
  int64_t DataVersionAfterCommit(int64_t read, int64_t /*tx*/) const override { return read; }

  // BEGIN IMMEDIATE: the write lock is taken at once, so a second writer waits (busy timeout)
  // here rather than failing at its first write.
  Status BeginWrite() override;
  // BEGIN DEFERRED plus one read, as a deferred transaction takes its snapshot at the first read.
  Status BeginRead() override;
  Status Commit() override;
  Status Rollback() override;
  Status BeginSavepoint(std::string_view name) override;
  Status ReleaseSavepoint(std::string_view name) override;
  Status RollbackToSavepoint(std::string_view name) override;
  bool InTransaction() const override;

  // PRAGMA application_id and PRAGMA user_version.
  Result<int64_t> ApplicationId() override;
  Status SetApplicationId(int32_t id) override;
  Result<int64_t> SchemaVersion() override;
  Status SetSchemaVersion(int64_t version) override;

  // WAL journal (on create), foreign keys on, synchronous NORMAL (durable at checkpoints, never
  // corrupt: docs/design.md, Pitfalls we already know of), the memory map, and for a writer a
  // WalCheckpointer. A writer opening a store that was not closed cleanly (SQLite had to recover
  // its WAL) runs PRAGMA quick_check first: Corruption naming `tinbase check` and the recovery
  // path when the file fails it, so nothing is written to a damaged store.
  Status ConfigureForStore(const StoreSettings& settings) override;
  // Unlike PRAGMA foreign_keys this also works inside a transaction; statements prepared before
  // are re-prepared on their next step.
  Result<bool> SetForeignKeys(bool on) override;
  // A ScopedPageCache (db/sqlite/scoped_page_cache.h), or null when it leaves the cache alone.
  std::unique_ptr<Scope> BeginLargeWrite(size_t rows) override;
  // INSERT OR FAIL (db/sql/bulk_write.h says why).
  std::string_view BulkInsertHead() const override { return "INSERT OR FAIL INTO "; }
  Backend backend() const override { return Backend::kSqlite; }
  const std::string& path() const override { return path_; }

  // The C handle, for the rest of db/sqlite/ (WalCheckpointer) only.
  sqlite3* handle() const { return db_; }

 private:
  SqliteConnection(sqlite3* db, std::string path);
  Status CheckAfterUncleanShutdown();
  sqlite3* db_;
  std::string path_;
  std::unordered_map<std::string, std::unique_ptr<SqliteStatement>> cache_;
  // Destroyed before the connection closes (the destructor resets it first).
  std::unique_ptr<WalCheckpointer> checkpointer_;
};

}  // namespace tinbase
