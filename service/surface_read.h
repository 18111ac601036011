// SurfaceRead: what every surface read route starts with: a reader connection from the pool, one
// read snapshot (so all the queries of an answer see one state, whatever writers commit
// meanwhile), the surface the path names, and the store's CRS.
// Thread-safety: one per request.
#pragma once

#include <httplib.h>

#include <memory>
#include <optional>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "db/store.h"
#include "db/surface_store.h"
#include "service/client_crs.h"
#include "service/service_context.h"

namespace tinbase::service {

struct SurfaceRead {
  StoreLease lease;  // declared first: the snapshot ends before the connection goes back
  std::unique_ptr<ReadSnapshot> snapshot;
  SurfaceInfo surface;
  const StoreCrs* crs = nullptr;  // the store's (this thread's cache); null when it has none

  Store& store() { return lease.store(); }
};

// Begins the read of the surface named by path capture 1. NotFound "no surface named 'x'";
// Busy or IOError from the pool.
Result<SurfaceRead> BeginSurfaceRead(ServiceContext& context, const httplib::Request& req);

}  // namespace tinbase::service
