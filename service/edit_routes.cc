// The edit routes: features posted, replaced and removed through the transactional engine.
#include "service/routes.h"

namespace tinbase::service {

void RegisterEditRoutes(httplib::Server& /*server*/, ServiceContext& /*context*/) {}

}  // namespace tinbase::service
