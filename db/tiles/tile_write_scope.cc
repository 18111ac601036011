// TileWriteScope of tile_write_scope.h.
#include "db/tiles/tile_write_scope.h"

#include <utility>

namespace tinbase {

Result<TileWriteScope> TileWriteScope::Begin(Store& store) {
  if (store.db().InTransaction()) return TileWriteScope(nullptr);
  TB_ASSIGN_OR_RETURN(std::unique_ptr<WriteTransaction> own, store.BeginWrite());
  return TileWriteScope(std::move(own));
}

Status TileWriteScope::Commit() { return own_ ? own_->Commit() : Status::Ok(); }

}  // namespace tinbase
