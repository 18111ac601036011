// The DEM routes: the index map, GeoTIFF windows and edge-collapsed TINs of a box.
#include "service/routes.h"

namespace tinbase::service {

void RegisterDemRoutes(httplib::Server& /*server*/, ServiceContext& /*context*/) {}

}  // namespace tinbase::service
