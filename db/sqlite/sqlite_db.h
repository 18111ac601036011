// SqliteDb and Statement: a thin RAII layer over the SQLite C API.
//
// All SQLite return codes become Status values in exactly one function, StatusFromSqlite(), so the
// rest of db/ never sees an `int rc`. A SqliteDb owns one connection and a cache of prepared
// statements (prepare once, reuse: DESIGN.md's SQLite pitfalls). Thread-safety: a connection and
// its statements belong to one thread at a time; open one SqliteDb per thread.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "core/base/status.h"

struct sqlite3;
struct sqlite3_stmt;

namespace tinbase {

// Maps an SQLite result code (and the connection's message) to a Status. `context` says what was
// being done ("inserting triangles").
Status StatusFromSqlite(int rc, sqlite3* db, std::string_view context);

class Statement {
 public:
  Statement(sqlite3* db, sqlite3_stmt* stmt, std::string sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  // Parameters are 1-based, as in SQLite. Binding errors surface at Step().
  Statement& Bind(int index, int64_t value);
  Statement& Bind(int index, double value);
  Statement& Bind(int index, std::string_view text);
  // Binds `text` without copying it (Bind copies). REQUIRES: `text` is NUL-terminated and
  // outlives every execution of the statement with this binding (a string literal).
  Statement& BindStaticText(int index, const char* text);
  Statement& BindBlob(int index, const void* data, size_t size);
  Statement& BindNull(int index);

  // Advances to the next row: true when a row is available, false when done.
  Result<bool> Step();
  // Steps until done (for statements that return no rows); then resets.
  Status Run();
  // Resets for re-execution and clears bindings.
  void Reset();

  int ColumnCount() const;
  int64_t ColumnInt(int index) const;
  double ColumnDouble(int index) const;
  std::string ColumnText(int index) const;
  bool ColumnIsNull(int index) const;
  // Bytes of a BLOB column; valid until the next Step/Reset.
  const uint8_t* ColumnBlob(int index, size_t* size) const;

  const std::string& sql() const { return sql_; }

 private:
  sqlite3* db_;
  sqlite3_stmt* stmt_;
  std::string sql_;
};

class SqliteDb {
 public:
  enum class Mode { kReadOnly, kReadWrite, kCreate };

  // Opens `path`. kCreate makes a new file and fails if one exists; the other modes fail with
  // NotFound when it does not exist.
  static Result<std::unique_ptr<SqliteDb>> Open(const std::string& path, Mode mode);
  ~SqliteDb();
  SqliteDb(const SqliteDb&) = delete;
  SqliteDb& operator=(const SqliteDb&) = delete;

  // Runs one or more statements that return no rows.
  Status Exec(std::string_view sql);
  // A prepared statement owned by the caller.
  Result<std::unique_ptr<Statement>> Prepare(std::string_view sql);
  // A cached prepared statement for `sql`, reset and ready to bind. Owned by this connection.
  Result<Statement*> Cached(std::string_view sql);
  // The single integer a query returns (first column of the first row).
  Result<int64_t> QueryInt(std::string_view sql);

  int64_t LastInsertRowId() const;
  int64_t Changes() const;
  // Turns the enforcement of foreign keys on or off and returns whether it was on. Unlike
  // PRAGMA foreign_keys this also works inside a transaction (db/sqlite/unchecked_foreign_keys.h
  // is the only user); statements prepared before are re-prepared on their next step.
  Result<bool> SetForeignKeys(bool on);
  sqlite3* handle() const { return db_; }
  const std::string& path() const { return path_; }

 private:
  SqliteDb(sqlite3* db, std::string path) : db_(db), path_(std::move(path)) {}
  sqlite3* db_;
  std::string path_;
  std::unordered_map<std::string, std::unique_ptr<Statement>> cache_;
};

}  // namespace tinbase
