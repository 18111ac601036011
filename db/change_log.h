// ChangeLog: the append-only `changes` table, one row per write transaction that changes a
// surface, so clients can ask what changed since a transaction and refresh only those tiles.
// Thread-safety: through one Store.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "db/store.h"

namespace tinbase {

struct Change {
  int64_t tx = 0;    // assigned by AppendChange
  std::string time;  // UTC, ISO 8601; assigned by AppendChange
  std::optional<int64_t> surface;
  std::optional<int64_t> feature;
  std::string action;                                 // "build", "polygon add", ...
  int64_t removed = 0;                                // triangles removed
  int64_t added = 0;                                  // triangles added
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;  // the changed region
  // The features the transaction added, changed or removed, in id order (their versions,
  // db/history/feature_versions.h); filled by ChangesSince, ignored by AppendChange.
  std::vector<int64_t> features;
};

// Appends `change` and returns its transaction number. REQUIRES: inside a WriteTransaction.
Result<int64_t> AppendChange(Store& store, const Change& change);
// The change of transaction `tx`, with the features it touched. NotFound "no transaction 12".
Result<Change> ChangeOf(Store& store, int64_t tx);
// The number of the last transaction; 0 for a store with none.
Result<int64_t> LastTransaction(Store& store);
// The first change of surface `surface` (its build); nullopt when it has none.
Result<std::optional<Change>> FirstChangeOfSurface(Store& store, int64_t surface);
// The first change of surface `surface` after transaction `after` that wrote no feature version
// (a change of the mesh that is not a feature edit: a rebuild, new DEM data); nullopt when none.
Result<std::optional<Change>> FirstChangeWithoutFeatures(Store& store, int64_t surface,
                                                         int64_t after);
// The changes after transaction `since` that this connection sees, oldest first, with the
// features each touched.
Result<std::vector<Change>> ChangesSince(Store& store, int64_t since);

// Readers that keep the last number they have seen and next ask for the changes after it (the
// change feed, `tiles update`). With concurrent writers (PostgreSQL) numbers commit out of
// order: a number below one a reader has seen may still commit, and a reader that moved past it
// would miss it for ever. Such a reader moves its mark only as far as SettledThrough.

// How far a reader may move its mark after reading `changes` (ChangesSince(store, since)), when
// `settled` is SettledChange(store.db()) (db/sql/settled_change.h) taken before that read's
// snapshot: to the last of them before the first number it did not see that may still commit (one
// above `settled` not yet seen); `since` when that is the first.
int64_t SettledThrough(int64_t since, const std::vector<Change>& changes, int64_t settled);
// The changes after `since` up to SettledThrough: reading again after the last one misses none.
// REQUIRES: outside a transaction, or in one begun by BeginRegionWrite or BeginWrite.
Result<std::vector<Change>> SettledChangesSince(Store& store, int64_t since);
// The largest number up to which every change that will commit is seen (the mark of a reader
// that starts now); 0 for a store with none.
Result<int64_t> SettledLastTransaction(Store& store);
// The number of changes seen. Rows are never deleted, so it grows with every commit that
// appends one, on either backend: a cache of what the rows hold is stale when it moved (the
// largest number would not do: with concurrent writers a smaller one may commit after it).
Result<int64_t> ChangeCount(Store& store);

}  // namespace tinbase
