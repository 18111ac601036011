// SpiConnection and SpiStatement: the storage seam (db/sql/connection.h) inside a PostgreSQL
// backend, over SPI, so the tinbase engine runs in the server and every row it writes is part of
// the caller's transaction (a ROLLBACK undoes the edit).
//
// One SpiConnection serves one call of an extension function: the entry point connects SPI, opens
// this (which begins a guard subtransaction and pins search_path to the store's schema), runs the
// engine, and calls Finish. Transactions of the engine nest inside the guard as internal
// subtransactions: BeginWrite/Commit/Rollback and the savepoints map onto
// BeginInternalSubTransaction, ReleaseCurrentSubTransaction and
// RollbackAndReleaseCurrentSubTransaction, so "commit" hands the rows to the caller's transaction
// and "rollback" drops only the engine's own work. BeginWrite also takes the store's
// transaction-scoped advisory lock, the one db/postgres/pg_connection.cc takes, so the CLI and the
// extension serialise as two CLI writers do; the caller's transaction holds it until it ends.
//
// PostgreSQL reports errors by longjmp. Every SPI and catalogue call here runs under PG_TRY; an
// error is caught there, every subtransaction of this connection (the guard included) is rolled
// back at once, which is the recovery PostgreSQL demands before any other server call, and the
// error becomes a Status; from then on every call answers that Status without touching the
// server. The entry point turns the failed Status into ereport(ERROR) once no C++ object is
// alive, so neither a longjmp nor a C++ exception crosses the other's frames.
// Thread-safety: a backend is single-threaded; one SpiConnection at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "db/sql/connection.h"

namespace tinbase {

class SpiConnection;

class SpiStatement final : public Statement {
 public:
  SpiStatement(SpiConnection* db, std::string sql, void* plan, std::vector<unsigned> types);
  ~SpiStatement() override;

  SpiStatement& Bind(int index, int64_t value) override;
  SpiStatement& Bind(int index, double value) override;
  SpiStatement& Bind(int index, std::string_view text) override;
  SpiStatement& BindStaticText(int index, const char* text) override;
  SpiStatement& BindBlob(int index, const void* data, size_t size) override;
  SpiStatement& BindNull(int index) override;

  Result<bool> Step() override;
  Status Run() override;
  void Reset() override;

  int ColumnCount() const override;
  int64_t ColumnInt(int index) const override;
  double ColumnDouble(int index) const override;
  std::string ColumnText(int index) const override;
  bool ColumnIsNull(int index) const override;
  const uint8_t* ColumnBlob(int index, size_t* size) const override;

  // Called by the connection when the subtransaction that made this statement's rows is rolled
  // back (PostgreSQL has freed them).
  void ForgetRows();
  int depth() const { return depth_; }
  void set_depth(int depth) { depth_ = depth; }

 private:
  enum class Kind { kNull, kInt, kDouble, kText, kBlob };
  struct Parameter {
    Kind kind = Kind::kNull;
    int64_t i = 0;
    double d = 0;
    std::string text;  // kText, kBlob
  };
  Parameter& At(int index);
  Status Execute();
  std::string ValueText(int index) const;

  SpiConnection* db_;
  void* plan_;                   // SPIPlanPtr, freed with the SPI connection
  std::vector<unsigned> types_;  // the parameters' type oids
  std::vector<Parameter> parameters_;
  void* rows_ = nullptr;  // SPITupleTable*
  uint64_t row_count_ = 0;
  int64_t row_ = -1;
  int depth_ = 0;  // the connection's depth when the rows were made
};

class SpiConnection final : public Connection {
 public:
  // Opens the connection of one call on the store in `schema` (the extension's schema), with
  // `search_path` (the path CREATE EXTENSION ran with). REQUIRES: SPI connected.
  static Result<std::unique_ptr<SpiConnection>> Open(const std::string& schema,
                                                     const std::string& search_path);
  ~SpiConnection() override;

  // Ends the call: on `ok` the guard subtransaction is released (its rows stay in the caller's
  // transaction), else rolled back. Returns the error that poisoned the connection, if any.
  Status Finish(bool ok);
  // Sets search_path for the rest of the call (restored by Finish).
  Status SetSearchPath(const std::string& path);

  Status Exec(std::string_view sql) override;
  Result<std::unique_ptr<Statement>> Prepare(std::string_view sql) override;
  Result<Statement*> Cached(std::string_view sql) override;

  int64_t Changes() const override { return changes_; }
  int64_t TotalChanges() const override { return total_changes_; }
  // As PgConnection's: the newest `changes` row committed by another transaction.
  Result<int64_t> DataVersion() override;
  int64_t DataVersionAfterCommit(int64_t /*read*/, int64_t tx) const override { return tx; }

  Status BeginWrite() override;
  // The caller's snapshot: nothing to begin (each statement reads the caller's transaction).
  Status BeginRead() override;
  Status Commit() override;
  Status Rollback() override;
  Status BeginSavepoint(std::string_view name) override;
  Status ReleaseSavepoint(std::string_view name) override;
  Status RollbackToSavepoint(std::string_view name) override;
  bool InTransaction() const override { return !scopes_.empty(); }

  Result<int64_t> ApplicationId() override;
  Status SetApplicationId(int32_t id) override;
  Result<int64_t> SchemaVersion() override;
  Status SetSchemaVersion(int64_t version) override;

  Status ConfigureForStore(const StoreSettings& /*settings*/) override { return Status::Ok(); }
  // Foreign keys of the PostgreSQL schema are DEFERRABLE INITIALLY DEFERRED; they stay on.
  Result<bool> SetForeignKeys(bool /*on*/) override { return true; }
  std::unique_ptr<Scope> BeginLargeWrite(size_t /*rows*/) override { return nullptr; }
  std::string_view BulkInsertHead() const override { return "INSERT INTO "; }
  Backend backend() const override { return Backend::kPostgres; }
  const std::string& path() const override { return label_; }

  // For SpiStatement.
  const std::optional<Status>& poison() const { return poison_; }
  // Records a caught server error: rolls every subtransaction of this connection back and makes
  // every later call fail with it. Returns the Status.
  Status Poison(Status status);
  int depth() const { return static_cast<int>(saved_.size()); }
  void SetChanges(int64_t n) {
    changes_ = n;
    total_changes_ += n;
  }
  void Track(SpiStatement* statement) { live_[statement] = true; }
  void Untrack(SpiStatement* statement) { live_.erase(statement); }

 private:
  enum class ScopeKind { kRead, kSubtransaction };
  SpiConnection(std::string schema, std::string label);
  Status BeginSubtransaction();
  Status EndSubtransaction(bool commit);
  Status Pop(bool commit);
  Result<bool> HasStoreTable();

  std::string schema_;
  std::string label_;
  int64_t lock_key_;
  int64_t changes_ = 0;
  int64_t total_changes_ = 0;
  int guc_level_ = 0;
  // The engine's scopes, innermost last; the guard subtransaction is not among them.
  std::vector<ScopeKind> scopes_;
  // The memory context and resource owner before each open subtransaction (the guard first),
  // restored when it ends, as PL/Python does around its subtransactions.
  std::vector<std::pair<void*, void*>> saved_;
  bool guard_open_ = false;
  std::optional<Status> poison_;
  std::unordered_map<std::string, std::unique_ptr<SpiStatement>> cache_;
  std::unordered_map<SpiStatement*, bool> live_;
};

}  // namespace tinbase
