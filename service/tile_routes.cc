// The terrain tiles of a surface's stored pyramids, as Cesium asks for them.
#include "service/routes.h"

namespace tinbase::service {

void RegisterTileRoutes(httplib::Server& /*server*/, ServiceContext& /*context*/) {}

}  // namespace tinbase::service
