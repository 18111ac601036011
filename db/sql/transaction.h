// Transaction, Snapshot and Savepoint: the scopes of work on a Connection, each undone in its
// destructor unless finished (jtv/libpqxx's pqxx::work is the model).
//
// A Transaction is the single write transaction of a store: it rolls back when destroyed
// uncommitted, on every path, so an early `return status;` never leaves half a write. A Snapshot
// is a read transaction whose view of the store stays fixed across several queries. A Savepoint
// nests inside a transaction and undoes only its own part. Store's WriteTransaction and
// ReadSnapshot (db/store.h) are built on these; code above the Store uses those.
// Thread-safety: as the connection.
#pragma once

#include <string>

#include "core/base/status.h"
#include "db/sql/connection.h"

namespace tinbase {

class Transaction {
 public:
  // Begins the write transaction; Busy if another writer holds the store for too long.
  static Result<Transaction> Begin(Connection& db);
  // Begins the write transaction of an edit of one region of a surface
  // (Connection::BeginRegionWrite): other region writers do not wait for it.
  static Result<Transaction> BeginRegion(Connection& db);
  Transaction(Transaction&& other) noexcept : db_(other.db_) { other.db_ = nullptr; }
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  Transaction& operator=(Transaction&&) = delete;
  ~Transaction();

  // Makes every change since Begin durable. On failure nothing of it is kept (rolled back).
  // REQUIRES: not committed yet.
  Status Commit();

 private:
  explicit Transaction(Connection& db) : db_(&db) {}
  Connection* db_;  // null once committed or moved from
};

class Snapshot {
 public:
  // Begins a read transaction with its snapshot pinned.
  static Result<Snapshot> Begin(Connection& db);
  Snapshot(Snapshot&& other) noexcept : db_(other.db_) { other.db_ = nullptr; }
  Snapshot(const Snapshot&) = delete;
  Snapshot& operator=(const Snapshot&) = delete;
  Snapshot& operator=(Snapshot&&) = delete;
  // Ends the read transaction.
  ~Snapshot();

 private:
  explicit Snapshot(Connection& db) : db_(&db) {}
  Connection* db_;
};

class Savepoint {
 public:
  // Opens savepoint `name` (an SQL identifier). REQUIRES: inside a transaction.
  static Result<Savepoint> Begin(Connection& db, std::string name);
  Savepoint(Savepoint&& other) noexcept : db_(other.db_), name_(std::move(other.name_)) {
    other.db_ = nullptr;
  }
  Savepoint(const Savepoint&) = delete;
  Savepoint& operator=(const Savepoint&) = delete;
  Savepoint& operator=(Savepoint&&) = delete;
  // Rolls the changes since Begin back (the enclosing transaction goes on) unless released.
  ~Savepoint();

  // Keeps the changes since Begin as part of the enclosing transaction.
  Status Release();

 private:
  Savepoint(Connection& db, std::string name) : db_(&db), name_(std::move(name)) {}
  Connection* db_;
  std::string name_;
};

}  // namespace tinbase
