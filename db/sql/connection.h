// Connection and Statement: the one seam between tinbase's storage code and a database backend,
// as LevelDB's Env is the one seam to the operating system.
//
// Everything in db/ above the seam (Store, the stores of DEMs, surfaces and features, the update
// engine, the checker) talks to a Connection and its Statements only. The SQLite backend lives in
// db/sqlite/ (SqliteConnection) and is the only code that sees the C API of its library. The RAII
// objects built on this interface are in db/sql/transaction.h (write transaction, read snapshot,
// savepoint), db/sql/large_write_hint.h and db/sql/unchecked_foreign_keys.h.
//
// What a second backend (say PostgreSQL through libpq, in db/postgres/) must provide:
//   - a Connection subclass implementing every pure virtual below, and a Statement subclass with
//     1-based parameters and 0-based columns (libpq's $1, $2 ... map one to one);
//   - one function mapping its native errors to Status (SQLSTATE classes 40001/55P03 -> Busy,
//     23xxx -> Conflict, XX001/XX002 -> Corruption, ...), as StatusFromSqlite does for SQLite:
//     no other code looks at a native error;
//   - a branch in Connection::Open (db/sql/connection.cc) that recognises its targets;
//   - its own numbered migrations (the SQL dialect of the tables is the backend's) and the
//     store-identity calls (ApplicationId, SchemaVersion) kept wherever the backend can.
// The tuning calls (SetForeignKeys, BeginLargeWrite, ConfigureForStore) are hints: a backend that
// has nothing to tune answers them without effect, and results must not depend on them.
//
// Thread-safety: a connection and its statements belong to one thread at a time; open one
// connection per thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/status.h"

namespace tinbase {

// A prepared statement. Parameters are 1-based, columns 0-based. Binding errors surface at
// Step(). Owned by the caller (Connection::Prepare) or by the connection (Connection::Cached).
class Statement {
 public:
  virtual ~Statement() = default;
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  virtual Statement& Bind(int index, int64_t value) = 0;
  virtual Statement& Bind(int index, double value) = 0;
  virtual Statement& Bind(int index, std::string_view text) = 0;
  // Binds `text` without copying it (Bind copies). REQUIRES: `text` is NUL-terminated and
  // outlives every execution of the statement with this binding (a string literal).
  virtual Statement& BindStaticText(int index, const char* text) = 0;
  virtual Statement& BindBlob(int index, const void* data, size_t size) = 0;
  virtual Statement& BindNull(int index) = 0;

  // Advances to the next row: true when a row is available, false when done; the mapped error
  // otherwise (Busy, Conflict for a broken constraint, Corruption, ...).
  virtual Result<bool> Step() = 0;
  // Steps until done (for statements that return no rows); then resets.
  virtual Status Run() = 0;
  // Resets for re-execution and clears bindings.
  virtual void Reset() = 0;

  virtual int ColumnCount() const = 0;
  virtual int64_t ColumnInt(int index) const = 0;
  virtual double ColumnDouble(int index) const = 0;
  virtual std::string ColumnText(int index) const = 0;
  virtual bool ColumnIsNull(int index) const = 0;
  // Bytes of a BLOB column; valid until the next Step/Reset.
  virtual const uint8_t* ColumnBlob(int index, size_t* size) const = 0;

  const std::string& sql() const { return sql_; }

 protected:
  explicit Statement(std::string sql) : sql_(std::move(sql)) {}

 private:
  std::string sql_;
};

// Rows streamed into one table for a bulk write: bind a row's values as a statement's
// parameters (1-based, one per column), then Run() (or Step()) ends the row; Finish() ends the
// stream and gives the first error of any row. Made by Connection::BeginRowStream; until it is
// finished or destroyed the connection runs no other statement (PostgreSQL's COPY holds it).
// Destroying an unfinished stream abandons it: its rows are not written, and the caller's
// transaction fails. db/sql/bulk_write.h is the only user.
class RowStream : public Statement {
 public:
  virtual Status Finish() = 0;

  int ColumnCount() const override { return 0; }
  int64_t ColumnInt(int /*index*/) const override { return 0; }
  double ColumnDouble(int /*index*/) const override { return 0; }
  std::string ColumnText(int /*index*/) const override { return {}; }
  bool ColumnIsNull(int /*index*/) const override { return true; }
  const uint8_t* ColumnBlob(int /*index*/, size_t* size) const override {
    *size = 0;
    return nullptr;
  }
  void Reset() override {}

 protected:
  using Statement::Statement;
};

// Runs `insert`, an INSERT (or UPDATE) ending in "RETURNING id", and gives the id of its row;
// then resets it. Both backends speak RETURNING, where a last-insert id is SQLite's alone.
Result<int64_t> RunReturningId(Statement& insert);

// How a store's connection is set up (Store::Create and Store::Open pass it on).
struct StoreSettings {
  bool create = false;  // the store was just created: make its durable settings (a log mode)
  bool writer = false;  // the connection will write: keep log maintenance off the commit path
  // How much of the file may be read through a memory map (0: none); backends without a map
  // ignore it.
  int64_t memory_map_bytes = 0;
};

// The database systems behind the seam. Only the migrations differ by backend; no code above the
// seam asks.
enum class Backend { kSqlite, kPostgres };

class Connection {
 public:
  enum class Mode { kReadOnly, kReadWrite, kCreate };

  // Opens `target` with the backend it names (today every target is an SQLite file path).
  // kCreate makes a new store file and fails with InvalidArgument if one exists; the other
  // modes fail with NotFound when it does not exist. The connection is bare: Store calls
  // ConfigureForStore.
  static Result<std::unique_ptr<Connection>> Open(const std::string& target, Mode mode);

  virtual ~Connection() = default;
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  // --- statements ---------------------------------------------------------------------------

  // Runs one or more statements that return no rows.
  virtual Status Exec(std::string_view sql) = 0;
  // A prepared statement owned by the caller.
  virtual Result<std::unique_ptr<Statement>> Prepare(std::string_view sql) = 0;
  // A cached prepared statement for `sql`, reset and ready to bind, owned by this connection:
  // prepare once, reuse (docs/design.md, Pitfalls we already know of). Valid until the connection
  // closes.
  virtual Result<Statement*> Cached(std::string_view sql) = 0;
  // The single integer a query returns (first column of the first row); NotFound for no row.
  Result<int64_t> QueryInt(std::string_view sql);

  // Rows changed by the last statement, and by all statements since the connection opened.
  virtual int64_t Changes() const = 0;
  virtual int64_t TotalChanges() const = 0;
  // A number that changes when another connection commits a change to the store: caches compare
  // it to know they are stale. Read inside a write transaction whose `changes` row is `tx`, it is
  // `read`; the value the next read will give if no other connection commits in between is
  // DataVersionAfterCommit(read, tx) (SQLite's own commits leave it as it is; PostgreSQL's is the
  // newest transaction number, then this one's).
  virtual Result<int64_t> DataVersion() = 0;
  virtual int64_t DataVersionAfterCommit(int64_t read, int64_t tx) const = 0;

  // --- transactions (use db/sql/transaction.h rather than these) ----------------------------

  // Starts the single write transaction of the store (other writers wait; Busy after the
  // backend's timeout); readers keep their snapshots.
  virtual Status BeginWrite() = 0;
  // Starts a read transaction whose snapshot is pinned when this returns.
  virtual Status BeginRead() = 0;
  virtual Status Commit() = 0;
  virtual Status Rollback() = 0;
  // Named savepoints nest inside a transaction. RollbackToSavepoint undoes the changes since the
  // savepoint and keeps it open; ReleaseSavepoint keeps the changes and closes it.
  virtual Status BeginSavepoint(std::string_view name) = 0;
  virtual Status ReleaseSavepoint(std::string_view name) = 0;
  virtual Status RollbackToSavepoint(std::string_view name) = 0;
  // True inside a transaction begun by any of the above.
  virtual bool InTransaction() const = 0;

  // --- the store's identity -----------------------------------------------------------------

  // The mark that tells a tinbase store from other files of the backend (0 when none), and
  // setting it. Fails (Corruption) when the target is not a database of the backend at all.
  virtual Result<int64_t> ApplicationId() = 0;
  virtual Status SetApplicationId(int32_t id) = 0;
  // The number of the last migration applied (0 for an empty store), and setting it.
  // REQUIRES for the setter: inside the migration's write transaction.
  virtual Result<int64_t> SchemaVersion() = 0;
  virtual Status SetSchemaVersion(int64_t version) = 0;

  // --- tuning hints -------------------------------------------------------------------------

  // Makes a bare connection a store's: the backend's durability and caching settings, foreign
  // keys enforced, and (settings.writer) log maintenance off the commit path.
  virtual Status ConfigureForStore(const StoreSettings& settings) = 0;
  // Turns the enforcement of foreign keys on or off and returns whether it was on; works inside
  // a transaction. db/sql/unchecked_foreign_keys.h is the only user.
  virtual Result<bool> SetForeignKeys(bool on) = 0;
  // Whatever a hint changed, undone when destroyed.
  class Scope {
   public:
    virtual ~Scope() = default;
  };
  // Says that a write of about `rows` rows follows in this transaction; null when the backend
  // changes nothing for it. Destroy the scope after the commit. db/sql/large_write_hint.h wraps
  // it.
  virtual std::unique_ptr<Scope> BeginLargeWrite(size_t rows) = 0;
  // The head of a multi-row INSERT that may stop at its first bad row without undoing the rows
  // before it (every caller rolls its transaction back on error), e.g. "INSERT INTO ". Used by
  // db/sql/bulk_write.h.
  virtual std::string_view BulkInsertHead() const = 0;

  // A stream of rows into `table_and_columns` ("table(a, b)", `columns` names) inside the open
  // write transaction, for a backend that has a faster way to write many rows than multi-row
  // INSERTs (PostgreSQL's COPY); null when it has none, and the caller inserts. Rows go through
  // the table's triggers and constraints as inserted ones do.
  virtual Result<std::unique_ptr<RowStream>> BeginRowStream(std::string_view /*table_and_columns*/,
                                                            int /*columns*/) {
    return std::unique_ptr<RowStream>();
  }

  // Which list of migrations this store takes (db/migrations.h).
  virtual Backend backend() const = 0;

  // What Open was given.
  virtual const std::string& path() const = 0;

  // --- concurrent writers (docs/scaling.md, "Writers") -------------------------------------
  // A backend with one writer per store (SQLite) keeps the defaults: its ids stay 1 + the largest
  // of their table, a region write is the store's one write transaction, and LockRegion has
  // nothing to do.

  // Whether writers of distant regions of one surface may commit at once; their edits then retry
  // on Busy (db/polygon_editor.cc).
  virtual bool ConcurrentWriters() const { return false; }
  // The first of `count` (>= 1) consecutive ids that no row holds and no other writer is given,
  // for new rows of `table` (a table numbered by its `id` column). SQLite: 1 + the largest id of
  // the table, right for its single writer. PostgreSQL (any connection of that backend, also
  // one inside the server): a run of the table's sequence (migration 0017).
  virtual Result<int64_t> ReserveIds(std::string_view table, int64_t count);
  // Whether a row inserted without an id gets 1 + the largest id of its table (SQLite); when not
  // (PostgreSQL's sequences), bulk writes give each row its reserved id (db/sql/bulk_write.h
  // InsertNumberedRows).
  virtual bool NumbersRowsByLargestId() const { return backend() == Backend::kSqlite; }
  // Begins a write transaction that edits one region of a surface: with concurrent writers it
  // waits only for whole-store writers (BeginWrite), and the edit locks its region with
  // LockRegion before it writes. The default is BeginWrite.
  virtual Status BeginRegionWrite() { return BeginWrite(); }
  // Locks `blocks` (BlockGrid ids) of `surface`, or every block of it when `whole_surface`, until
  // the transaction ends: waits while another writer holds one of them. Rows another writer
  // committed since this transaction's snapshot then fail this transaction's writes with Busy,
  // and the caller retries the edit. REQUIRES: inside BeginRegionWrite. The default does nothing.
  virtual Status LockRegion(int64_t surface, const std::vector<int64_t>& blocks,
                            bool whole_surface);

 protected:
  Connection() = default;
};

}  // namespace tinbase
