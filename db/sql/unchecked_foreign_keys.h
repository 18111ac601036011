// UncheckedForeignKeys: foreign keys not enforced on a connection while it lives, for one bulk
// statement whose every key is known to hold.
//
// With a foreign key to check, SQLite runs an UPDATE that changes the key column in two passes
// (the rowids first, then a b-tree lookup per row) instead of one walk over the rows, and looks
// the parent up for every row, which dominated the update engine's repaint of ~1e5 triangles
// (their tag column references tags). Built on Connection::SetForeignKeys, so any backend that
// can switch enforcement per connection (PostgreSQL: session_replication_role) serves. Use it only
// where the code just made sure the keys exist (the engine interns every tag it writes in the same
// transaction); `tinbase check` still reads every tag through its parent. The previous setting
// comes back in the destructor, on every path. Thread-safety: as the connection.
#pragma once

#include "core/base/status.h"
#include "db/sql/connection.h"

namespace tinbase {

class UncheckedForeignKeys {
 public:
  // Turns enforcement off; the Status of the connection when that fails.
  static Result<UncheckedForeignKeys> Begin(Connection& db) {
    TB_ASSIGN_OR_RETURN(bool was_on, db.SetForeignKeys(false));
    return UncheckedForeignKeys(db, was_on);
  }
  UncheckedForeignKeys(UncheckedForeignKeys&& other) noexcept
      : db_(other.db_), was_on_(other.was_on_) {
    other.db_ = nullptr;
  }
  UncheckedForeignKeys(const UncheckedForeignKeys&) = delete;
  UncheckedForeignKeys& operator=(const UncheckedForeignKeys&) = delete;
  UncheckedForeignKeys& operator=(UncheckedForeignKeys&&) = delete;
  ~UncheckedForeignKeys() {
    if (db_ != nullptr && was_on_) (void)db_->SetForeignKeys(true);
  }

 private:
  UncheckedForeignKeys(Connection& db, bool was_on) : db_(&db), was_on_(was_on) {}
  Connection* db_;
  bool was_on_;
};

}  // namespace tinbase
