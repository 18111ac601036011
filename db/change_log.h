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
};

// Appends `change` and returns its transaction number. REQUIRES: inside a WriteTransaction.
Result<int64_t> AppendChange(Store& store, const Change& change);
// The changes after transaction `since`, oldest first.
Result<std::vector<Change>> ChangesSince(Store& store, int64_t since);

}  // namespace tinbase
