// SurfaceRead: a reader connection, a snapshot and the surface of one request.
#include "service/surface_read.h"

#include "service/request_params.h"

namespace tinbase::service {

Result<SurfaceRead> BeginSurfaceRead(ServiceContext& context, const httplib::Request& req) {
  TB_ASSIGN_OR_RETURN(StoreLease lease, context.stores().Reader());
  TB_ASSIGN_OR_RETURN(std::unique_ptr<ReadSnapshot> snapshot, ReadSnapshot::Begin(lease.store()));
  TB_ASSIGN_OR_RETURN(SurfaceInfo surface, SurfaceFromPath(lease.store(), req));
  TB_ASSIGN_OR_RETURN(const StoreCrs* crs, StoreCrs::Of(lease.store()));
  return SurfaceRead{std::move(lease), std::move(snapshot), std::move(surface), crs};
}

}  // namespace tinbase::service
