// The service's routes, one group per file, each registered on the server by HttpServer.
// Paths and answers are documented in docs/api.md.
#pragma once

#include <httplib.h>

#include "service/service_context.h"

namespace tinbase::service {

// GET /surfaces, /surfaces/{s}, locate, triangles, profile, measures, export (surface_routes.cc).
void RegisterSurfaceRoutes(httplib::Server& server, ServiceContext& context);
// GET /surfaces/{s}/tiles/layer.json and /tiles/{z}/{x}/{y}.terrain (tile_routes.cc).
void RegisterTileRoutes(httplib::Server& server, ServiceContext& context);
// GET /dems/{d}/overview.png, /clip, /tin (dem_routes.cc).
void RegisterDemRoutes(httplib::Server& server, ServiceContext& context);
// POST /surfaces/{s}/features, PUT and DELETE /surfaces/{s}/features/{id} (edit_routes.cc).
void RegisterEditRoutes(httplib::Server& server, ServiceContext& context);
// GET /changes?since=TX: server-sent events, or a long poll (change_routes.cc).
void RegisterChangeRoutes(httplib::Server& server, ServiceContext& context);
// GET / and the viewer's files from options().web_root (viewer_routes.cc).
void RegisterViewerRoutes(httplib::Server& server, ServiceContext& context);

}  // namespace tinbase::service
