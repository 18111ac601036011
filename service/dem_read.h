// DemRead: what every DEM read route starts with: a reader connection from the pool, one read
// snapshot (the DEM's description and its blocks from the same import, whatever imports commit
// meanwhile), and the DEM the path names.
// Thread-safety: one per request.
#pragma once

#include <httplib.h>

#include <memory>

#include "core/base/status.h"
#include "db/dem_store.h"
#include "db/store.h"
#include "service/service_context.h"

namespace tinbase::service {

struct DemRead {
  StoreLease lease;  // declared first: the snapshot ends before the connection goes back
  std::unique_ptr<ReadSnapshot> snapshot;
  DemInfo dem;

  Store& store() { return lease.store(); }
};

// Begins the read of the DEM named by path capture 1. NotFound naming the DEM; Busy or IOError
// from the pool.
Result<DemRead> BeginDemRead(ServiceContext& context, const httplib::Request& req);

}  // namespace tinbase::service
