// SurfaceSummaryCache: the part of a surface's description that costs a scan of its rows (its
// counts and its extent), kept per surface for as long as the change log's head stays the same.
// Every write that changes a surface's rows appends a change (db/change_log.h: builds, imports,
// edits), so the head, the number of changes (ChangeCount: with concurrent writers numbers
// commit out of order), names the state of the rows; GET /surfaces then costs a count of the
// change log instead of a scan of every vertex and triangle per call.
// Thread-safety: every member may be called from any thread (one mutex around the map; the scans
// run outside it).
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>

#include "core/base/status.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase::service {

struct SurfaceSummary {
  SurfaceCounts counts;
  // [min x, min y, min z, max x, max y, max z] of its vertices; null for a surface without any.
  nlohmann::json extent;
};

class SurfaceSummaryCache {
 public:
  // The counts and extent of `surface` as `store` holds them now: from the cache when it was
  // made at the log's current head, else read (in one snapshot) and kept. Errors are the reads'.
  Result<SurfaceSummary> Get(Store& store, const SurfaceInfo& surface);

 private:
  struct Entry {
    int64_t head = -1;  // the change log's head (ChangeCount) the entry was read at
    SurfaceSummary summary;
  };
  std::mutex mutex_;
  std::map<int64_t, Entry> entries_;  // by surface id
};

}  // namespace tinbase::service
