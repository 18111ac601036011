// The region lock of an edit: before the update engine writes, it locks the blocks its conflict
// region, the ring across R's outline and its paint cover (Connection::LockRegion), so that
// writers of distant regions of one surface commit side by side while writers whose regions meet
// wait for each other (docs/scaling.md, "Writers").
//
// The blocks are those of the surface's block grid (triangles.block) that R's box and the paint
// box, grown by one block on every side for the ring, cover; an edit whose blocks are too many to
// name one by one locks the whole surface, as does an edit of the whole surface. The lock is what
// makes overlapping edits wait; what makes them correct is the transaction's snapshot: a row
// another writer changed since then fails this edit's write of it (Busy), and the caller retries.
// A backend with one writer (SQLite) locks nothing.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/status.h"
#include "core/tin/block_grid.h"
#include "db/feature_store.h"
#include "db/sql/connection.h"

namespace tinbase {

// Above this many blocks an edit locks its whole surface. PostgreSQL keeps every lock a
// transaction holds in one shared table (max_locks_per_transaction times max_connections slots,
// 6400 by default), so a few writers side by side must stay well inside it.
inline constexpr size_t kMaxLockedBlocks = 512;

// The blocks of `grid` that `box` grown by one block covers, in id order; empty when they are
// more than kMaxLockedBlocks (or `box` is empty).
std::vector<int64_t> BlocksToLock(const BlockGrid& grid, const Box& box);

// Locks the region `box` (R's box and the paint box) of surface `surface` and the blocks `also`
// (those the edit repaints whole), or the whole surface when `whole_surface` or the box holds too
// many blocks. REQUIRES: inside the edit's write transaction (Store::BeginRegionWrite). Busy
// after the backend's lock timeout or on a deadlock.
Status LockEditRegion(Connection& db, int64_t surface, const BlockGrid& grid, const Box& box,
                      const std::vector<int64_t>& also, bool whole_surface);

}  // namespace tinbase
