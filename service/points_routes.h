// The survey point routes: POST /surfaces/{s}/points inserts the Point Z and MultiPoint Z
// features of a GeoJSON body into the surface as one `points` feature, and DELETE
// /surfaces/{s}/points/{id} takes such a feature out, through the same engine as `tinbase points
// add|remove` (db/edit/mass_points.h). As the feature edit routes (edit_routes.cc): the token and
// --read-only apply, the body is parsed and checked before the writer is taken, and the tile
// pyramids are brought up to date inside the edit's own transaction. Paths and answers are in
// docs/api.md.
#pragma once

#include <httplib.h>

#include "service/service_context.h"

namespace tinbase::service {

void RegisterPointsRoutes(httplib::Server& server, ServiceContext& context);

}  // namespace tinbase::service
