// The change feed: committed edits as server-sent events, or a long poll.
#include "service/routes.h"

namespace tinbase::service {

void RegisterChangeRoutes(httplib::Server& /*server*/, ServiceContext& /*context*/) {}

}  // namespace tinbase::service
