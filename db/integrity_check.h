// IntegrityCheck: verifies the invariants a store promises (DESIGN.md 1-5 and 8), as
// PRAGMA integrity_check does for SQLite. Each broken invariant is a coded Problem naming the
// surface and triangle, in a stable order (by surface, then triangle id), so the first one is
// what `tinbase check` reports. Thread-safety: reads through one Store.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "db/store.h"

namespace tinbase {

struct Problem {
  std::string code;  // e.g. "clockwise-triangle", "asymmetric-neighbour"; see docs/format.md
  int64_t surface = 0;
  std::optional<int64_t> triangle;
  std::string message;  // "surface 'terrain', triangle 412: vertices are clockwise"
};

struct CheckOptions {
  std::optional<std::string> surface;  // only this surface; default all
};

// The problems found (empty when the store is intact); a Status only when reading fails.
Result<std::vector<Problem>> CheckStore(Store& store, const CheckOptions& options = {});

}  // namespace tinbase
