// PgConnection and PgStatement: the PostgreSQL backend of the seam in db/sql/connection.h, a thin
// RAII layer over libpq (Debian: libpq-dev).
//
// A store is one PostgreSQL schema ("postgresql://...?schema=NAME", db/sql/store_url.h); the
// connection's search_path is that schema, then public (where PostGIS lives). The statements of
// db/ are written once, in the SQL both backends speak: `?` and `?N` parameters become `$N` here,
// and every row comes back in text form, parsed by the Column* getters. All SQLSTATEs become
// Status values in exactly one function, StatusFromPg().
//
// Writers (docs/scaling.md, "Writers"): a whole-store write (BeginWrite: tin build, dem import,
// ...) takes an advisory lock named after the schema, so every other writer waits for it
// (lock_timeout, then Busy); an edit of a region (BeginRegionWrite) takes the same lock shared, so
// edits run side by side, each in REPEATABLE READ, and locks the blocks of its region
// (LockRegion) before it writes. Of two edits whose rows meet, the later writer gets a
// serialisation failure (Busy) and retries. Readers never wait.
// Thread-safety: a connection and its statements belong to one thread at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "core/base/status.h"
#include "db/sql/connection.h"

struct pg_conn;
struct pg_result;

namespace tinbase {

// The Status of a failed libpq result: SQLSTATE class 40 (serialization failure, deadlock) and
// 55P03 (lock not available) and 57014 (canceled by a timeout) -> Busy, class 23 (integrity) ->
// Conflict, XX001/XX002 (data corrupted) -> Corruption, classes 22 and 42 (bad data, bad SQL) ->
// InvalidArgument, everything else (connection, resources) -> IOError. `context` says what was
// being done.
Status StatusFromPg(const pg_result* result, const pg_conn* conn, std::string_view context);

// `sql` in PostgreSQL's words: SQLite's `?` and `?N` parameters written as `$N`, and the lower-case
// word `by` (the column dem_blocks.by; tinbase writes SQL keywords in upper case) quoted, as it is
// a reserved word there. Quoted text, quoted names and comments are left alone.
std::string PostgresParameters(std::string_view sql);

// `value` as PostgreSQL reads a double back bit for bit: the shortest round-trip text
// (std::to_chars), and Infinity, -Infinity, NaN in its words.
std::string PostgresFloatText(double value);

class PgStatement final : public Statement {
 public:
  PgStatement(pg_conn* conn, std::string name, std::string sql, int64_t* changes);
  ~PgStatement() override;

  PgStatement& Bind(int index, int64_t value) override;
  PgStatement& Bind(int index, double value) override;
  PgStatement& Bind(int index, std::string_view text) override;
  PgStatement& BindStaticText(int index, const char* text) override;
  PgStatement& BindBlob(int index, const void* data, size_t size) override;
  PgStatement& BindNull(int index) override;

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
  struct Parameter {
    std::optional<std::string> value;  // nullopt: NULL
    bool binary = false;               // a blob, sent as bytes
  };
  Parameter& At(int index);
  Status Execute();

  pg_conn* conn_;
  std::string name_;
  int64_t* changes_;  // the connection's count of rows changed by the last statement
  std::vector<Parameter> parameters_;
  pg_result* result_ = nullptr;
  int row_ = -1;
  mutable std::vector<uint8_t> blob_;
};

class PgConnection final : public Connection {
 public:
  // Connects to `conninfo` (a libpq connection URI without tinbase's own parameters) and makes
  // `schema` the store's. kCreate creates the schema and fails with InvalidArgument when it
  // already holds a store; the other modes fail with NotFound when the schema does not exist.
  // `label` is what messages call the store (the URL without its password).
  static Result<std::unique_ptr<PgConnection>> Open(const std::string& conninfo,
                                                    const std::string& schema,
                                                    const std::string& label, Mode mode);
  ~PgConnection() override;

  Status Exec(std::string_view sql) override;
  Result<std::unique_ptr<Statement>> Prepare(std::string_view sql) override;
  Result<Statement*> Cached(std::string_view sql) override;

  int64_t Changes() const override { return changes_; }
  int64_t TotalChanges() const override { return total_changes_; }
  Result<int64_t> DataVersion() override;
  // The number of `changes` rows (each write transaction appends one): with concurrent writers
  // their numbers commit out of order, so the largest says nothing about the ones below it.
  int64_t DataVersionAfterCommit(int64_t read, int64_t /*tx*/) const override { return read + 1; }

  // READ COMMITTED plus the store's advisory write lock (see the file comment).
  Status BeginWrite() override;
  // The store's lock shared, taken before the transaction begins so that its snapshot is taken
  // after a whole-store writer committed; then REPEATABLE READ.
  Status BeginRegionWrite() override;
  bool ConcurrentWriters() const override { return true; }
  // A transaction-scoped advisory lock per block, keyed by the store, the surface and the block,
  // taken in one order by every writer (so two cannot deadlock on them), after the surface's
  // lock: shared for blocks, exclusive for the whole surface.
  Status LockRegion(int64_t surface, const std::vector<int64_t>& blocks,
                    bool whole_surface) override;
  // db/sql/settled_change.h. Outside a transaction: the change numbers drawn so far when no
  // other transaction holds a write lock on `changes`, else 0. Inside one: that value as read
  // before its snapshot was taken (BeginRegionWrite), the largest int64 under the store's
  // exclusive lock (BeginWrite), 0 in a read transaction.
  Result<int64_t> SettledChange();
  // REPEATABLE READ, READ ONLY, with its snapshot taken by a first query.
  Status BeginRead() override;
  Status Commit() override;
  Status Rollback() override;
  Status BeginSavepoint(std::string_view name) override;
  Status ReleaseSavepoint(std::string_view name) override;
  Status RollbackToSavepoint(std::string_view name) override;
  bool InTransaction() const override;

  // The row of the schema's tinbase_store table (0 when the schema has none).
  Result<int64_t> ApplicationId() override;
  Status SetApplicationId(int32_t id) override;
  Result<int64_t> SchemaVersion() override;
  Status SetSchemaVersion(int64_t version) override;

  Status ConfigureForStore(const StoreSettings& settings) override;
  // Foreign keys stay enforced: the PostgreSQL schema declares them DEFERRABLE INITIALLY
  // DEFERRED, so rows may come in any order within a transaction. Returns true.
  Result<bool> SetForeignKeys(bool on) override;
  std::unique_ptr<Scope> BeginLargeWrite(size_t /*rows*/) override { return nullptr; }
  std::string_view BulkInsertHead() const override { return "INSERT INTO "; }
  Backend backend() const override { return Backend::kPostgres; }
  const std::string& path() const override { return label_; }
  // COPY ... FROM STDIN (db/postgres/pg_copy.h).
  Result<std::unique_ptr<RowStream>> BeginRowStream(std::string_view table_and_columns,
                                                    int columns) override;

 private:
  PgConnection(pg_conn* conn, std::string schema, std::string label);
  Result<bool> HasStoreTable();
  // Releases the store's shared lock of BeginRegionWrite, if held.
  void ReleaseRegionWriteLock();
  // The key of the advisory lock of `surface` of this store.
  int64_t SurfaceLockKey(int64_t surface) const;
  // SettledChange as of now (see there).
  Result<int64_t> ReadSettledChange();

  pg_conn* conn_;
  std::string schema_;
  std::string label_;
  int64_t lock_key_;
  int64_t changes_ = 0;
  int64_t total_changes_ = 0;
  int next_statement_ = 0;
  bool region_write_lock_ = false;  // the store's lock held shared, by BeginRegionWrite
  int64_t settled_at_begin_ = 0;    // SettledChange of the open transaction
  std::unordered_map<std::string, std::unique_ptr<PgStatement>> cache_;
};

}  // namespace tinbase
