// TileWriteScope: where a tile build or update writes. Alone (`tinbase tiles build|update`) it is
// the build's own write transaction; called from inside a write transaction (an edit that commits
// its tiles with it, as `tinbase serve` does) it is that transaction, so the edit and the tiles it
// changed become visible together or not at all.
// Thread-safety: as the Store.
#pragma once

#include <memory>

#include "core/base/status.h"
#include "db/store.h"

namespace tinbase {

class TileWriteScope {
 public:
  // Begins the store's write transaction unless one is open on its connection already. Busy as
  // Store::BeginWrite. REQUIRES: no read snapshot open on the connection.
  static Result<TileWriteScope> Begin(Store& store);

  // Commits the scope's own transaction. Inside the caller's transaction it does nothing: the
  // caller commits, and on any error the caller must roll back (a failed build may have written
  // part of a pyramid).
  Status Commit();

 private:
  explicit TileWriteScope(std::unique_ptr<WriteTransaction> own) : own_(std::move(own)) {}
  std::unique_ptr<WriteTransaction> own_;  // null inside the caller's transaction
};

}  // namespace tinbase
