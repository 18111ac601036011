#include "db/sql/transaction.h"

namespace tinbase {

Result<Transaction> Transaction::Begin(Connection& db) {
  TB_RETURN_IF_ERROR(db.BeginWrite());
  return Transaction(db);
}

Result<Transaction> Transaction::BeginRegion(Connection& db) {
  TB_RETURN_IF_ERROR(db.BeginRegionWrite());
  return Transaction(db);
}

Transaction::~Transaction() {
  if (db_ != nullptr) (void)db_->Rollback();
}

Status Transaction::Commit() {
  Connection* db = db_;
  db_ = nullptr;
  Status s = db->Commit();
  if (!s.ok()) (void)db->Rollback();
  return s;
}

Result<Snapshot> Snapshot::Begin(Connection& db) {
  TB_RETURN_IF_ERROR(db.BeginRead());
  return Snapshot(db);
}

Snapshot::~Snapshot() {
  if (db_ != nullptr) (void)db_->Commit();
}

Result<Savepoint> Savepoint::Begin(Connection& db, std::string name) {
  TB_RETURN_IF_ERROR(db.BeginSavepoint(name));
  return Savepoint(db, std::move(name));
}

Savepoint::~Savepoint() {
  if (db_ == nullptr) return;
  // Undo, then close: a savepoint rolled back to stays open until released.
  (void)db_->RollbackToSavepoint(name_);
  (void)db_->ReleaseSavepoint(name_);
}

Status Savepoint::Release() {
  Connection* db = db_;
  db_ = nullptr;
  return db->ReleaseSavepoint(name_);
}

}  // namespace tinbase
