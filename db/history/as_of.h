// AsOf: a surface as it was after a transaction, for reading (`export --as-of`; docs/design.md,
// "Undo and history"). The surface is taken back inside a write transaction that is never
// committed: the feature versions' net inverse (db/history/revert.h) is applied by the same local
// edits a revert makes, the reader reads the store through that transaction, and dropping it
// leaves the store as it was. It holds the store's write lock while it lives.
// Thread-safety: through one Store.
#pragma once

#include <cstdint>
#include <memory>

#include "core/base/status.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

// Begins a write transaction in which `surface` is as it was after transaction `tx`. The caller
// reads, then destroys the transaction without committing it. Errors as PlanAsOf, Busy when
// another writer holds the store, and the editor's; nothing is changed on any of them.
// REQUIRES: `store` opened for writing, no transaction open.
Result<std::unique_ptr<WriteTransaction>> BeginAsOf(Store& store, const SurfaceInfo& surface,
                                                    int64_t tx);

}  // namespace tinbase
