// DemRead: a reader connection, a snapshot and the DEM of one request.
#include "service/dem_read.h"

namespace tinbase::service {

Result<DemRead> BeginDemRead(ServiceContext& context, const httplib::Request& req) {
  if (req.matches.size() < 2) return Status::InvalidArgument("the path names no DEM");
  TB_ASSIGN_OR_RETURN(StoreLease lease, context.stores().Reader());
  TB_ASSIGN_OR_RETURN(std::unique_ptr<ReadSnapshot> snapshot, ReadSnapshot::Begin(lease.store()));
  DemStore dems(lease.store());
  TB_ASSIGN_OR_RETURN(DemInfo dem, dems.Find(req.matches[1].str()));
  return DemRead{std::move(lease), std::move(snapshot), std::move(dem)};
}

}  // namespace tinbase::service
