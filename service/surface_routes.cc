// The read routes of surfaces: GET /surfaces and /surfaces/{s} (what they are), and the
// registration of the queries and exports of docs/api.md (surface_route_parts.h).
#include <nlohmann/json.hpp>

#include "core/geometry/crs.h"
#include "db/surface_json.h"
#include "db/tiles/tile_store.h"
#include "service/client_crs.h"
#include "service/json_reply.h"
#include "service/request_params.h"
#include "service/routes.h"
#include "service/surface_route_parts.h"

namespace tinbase::service {

namespace {

// The extent's plan box in lon/lat [w, s, e, n]; null without a CRS or an extent.
Result<nlohmann::json> ExtentLonLat(const std::optional<Crs>& crs, const nlohmann::json& extent) {
  if (!extent.is_array()) return nlohmann::json(nullptr);
  TB_ASSIGN_OR_RETURN(auto box, BoxToLonLat(crs, extent[0].get<double>(), extent[1].get<double>(),
                                            extent[3].get<double>(), extent[4].get<double>()));
  return box ? nlohmann::json(*box) : nlohmann::json(nullptr);
}

// The names of the surface's tile pyramids: a store keeps at most one per surface
// (db/tiles/tile_store.h), named after the surface.
Result<nlohmann::json> TilePyramids(Store& store, const SurfaceInfo& s) {
  TB_ASSIGN_OR_RETURN(std::optional<TilePyramidInfo> pyramid, TileStore(store.db()).Pyramid(s.id));
  nlohmann::json names = nlohmann::json::array();
  if (pyramid) names.push_back(s.name);
  return names;
}

// A surface's description: the same fields as `tinbase info --json`, plus the store's CRS, the
// extent in lon/lat and the tile pyramids.
// The counts and extent come from the context's cache while the change log stands still.
Result<nlohmann::json> DescribeSurface(ServiceContext& context, Store& store,
                                       const SurfaceInfo& s) {
  TB_ASSIGN_OR_RETURN(SurfaceSummary summary, context.summaries().Get(store, s));
  TB_ASSIGN_OR_RETURN(std::optional<Crs> crs, store.GetCrs());
  nlohmann::json j = SurfaceSummaryJson(s, summary.counts);
  j["crs"] = crs ? nlohmann::json(crs->Label()) : nlohmann::json(nullptr);
  j["extent"] = summary.extent;
  TB_ASSIGN_OR_RETURN(j["extent_lonlat"], ExtentLonLat(crs, j["extent"]));
  TB_ASSIGN_OR_RETURN(j["tiles"], TilePyramids(store, s));
  return j;
}

void ListSurfaces(ServiceContext& context, httplib::Response& res) {
  auto lease = context.stores().Reader();
  if (!lease.ok()) return ReplyStatus(res, lease.status());
  auto list = SurfaceStore(lease->store()).List();
  if (!list.ok()) return ReplyStatus(res, list.status());
  nlohmann::json out = nlohmann::json::array();
  for (const SurfaceInfo& s : *list) {
    auto j = DescribeSurface(context, lease->store(), s);
    if (!j.ok()) return ReplyStatus(res, j.status());
    out.push_back(std::move(*j));
  }
  ReplyJson(res, {{"surfaces", out}});
}

void GetSurface(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto lease = context.stores().Reader();
  if (!lease.ok()) return ReplyStatus(res, lease.status());
  auto surface = SurfaceFromPath(lease->store(), req);
  if (!surface.ok()) return ReplyStatus(res, surface.status());
  auto j = DescribeSurface(context, lease->store(), *surface);
  if (!j.ok()) return ReplyStatus(res, j.status());
  ReplyJson(res, *j);
}

}  // namespace

void RegisterSurfaceRoutes(httplib::Server& server, ServiceContext& context) {
  server.Get("/surfaces", [&context](const httplib::Request&, httplib::Response& res) {
    ListSurfaces(context, res);
  });
  server.Get(R"(/surfaces/([^/]+))",
             [&context](const httplib::Request& req, httplib::Response& res) {
               GetSurface(context, req, res);
             });
  RegisterLocateRoutes(server, context);
  RegisterTriangleRoutes(server, context);
  RegisterFeatureReadRoutes(server, context);
  RegisterMeasureRoutes(server, context);
  RegisterExportRoute(server, context);
}

}  // namespace tinbase::service
