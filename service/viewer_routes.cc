// The web viewer: its page and its locally served JavaScript packages.
#include "service/routes.h"

namespace tinbase::service {

void RegisterViewerRoutes(httplib::Server& /*server*/, ServiceContext& /*context*/) {}

}  // namespace tinbase::service
