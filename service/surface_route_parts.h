// The parts of the surface read routes (docs/api.md), one file each, registered by
// RegisterSurfaceRoutes (surface_routes.cc) so routes.h keeps one entry per group.
#pragma once

#include <httplib.h>

#include "service/service_context.h"

namespace tinbase::service {

// GET and POST /surfaces/{s}/locate (locate_routes.cc).
void RegisterLocateRoutes(httplib::Server& server, ServiceContext& context);
// GET /surfaces/{s}/triangles/{id} and /surfaces/{s}/triangles?bbox= (triangle_routes.cc).
void RegisterTriangleRoutes(httplib::Server& server, ServiceContext& context);
// GET /surfaces/{s}/features and /surfaces/{s}/tags (feature_read_routes.cc).
void RegisterFeatureReadRoutes(httplib::Server& server, ServiceContext& context);
// GET /surfaces/{s}/profile and /surfaces/{s}/measures/area|volume|slope (measure_routes.cc).
void RegisterMeasureRoutes(httplib::Server& server, ServiceContext& context);
// GET /surfaces/{s}/export?format= (export_route.cc).
void RegisterExportRoute(httplib::Server& server, ServiceContext& context);

}  // namespace tinbase::service
