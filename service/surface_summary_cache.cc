// SurfaceSummaryCache of surface_summary_cache.h.
#include "service/surface_summary_cache.h"

#include <utility>

#include "db/change_log.h"

namespace tinbase::service {

namespace {

// The surface's extent: [min x, min y, min z, max x, max y, max z] of its vertices, or null.
Result<nlohmann::json> ReadExtent(Store& store, const SurfaceInfo& s) {
  TB_ASSIGN_OR_RETURN(Statement * q,
                      store.db().Cached("SELECT min(x), min(y), min(z), max(x), max(y), max(z) "
                                        "FROM vertices WHERE surface = ?"));
  q->Bind(1, s.id);
  TB_ASSIGN_OR_RETURN(bool row, q->Step());
  nlohmann::json extent = nullptr;
  if (row && !q->ColumnIsNull(0)) {
    extent = nlohmann::json::array();
    for (int i = 0; i < 6; ++i) extent.push_back(q->ColumnDouble(i));
  }
  q->Reset();
  return extent;
}

}  // namespace

Result<SurfaceSummary> SurfaceSummaryCache::Get(Store& store, const SurfaceInfo& surface) {
  // The head and the rows from one snapshot, so an entry never pairs a head with later rows.
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  TB_ASSIGN_OR_RETURN(const int64_t head, ChangeCount(store));
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = entries_.find(surface.id);
    if (it != entries_.end() && it->second.head == head) return it->second.summary;
  }
  SurfaceSummary summary;
  TB_ASSIGN_OR_RETURN(summary.counts, SurfaceStore(store).Count(surface));
  TB_ASSIGN_OR_RETURN(summary.extent, ReadExtent(store, surface));
  std::lock_guard<std::mutex> lock(mutex_);
  Entry& entry = entries_[surface.id];
  // A slower reader of an older snapshot must not put its rows back over a newer entry.
  if (head >= entry.head) entry = {head, summary};
  return summary;
}

}  // namespace tinbase::service
