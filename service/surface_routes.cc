// The read routes of surfaces: what they are, and the queries and exports of docs/api.md.
#include <nlohmann/json.hpp>

#include "core/geometry/crs.h"
#include "service/json_reply.h"
#include "service/request_params.h"
#include "service/routes.h"

namespace tinbase::service {

namespace {

// The surface's extent: [min x, min y, min z, max x, max y, max z] of its vertices.
Result<nlohmann::json> SurfaceExtent(Store& store, const SurfaceInfo& s) {
  TB_ASSIGN_OR_RETURN(Statement * q,
                      store.db().Cached("SELECT min(x), min(y), min(z), max(x), max(y), max(z) "
                                        "FROM vertices WHERE surface = ?"));
  q->Bind(1, s.id);
  TB_ASSIGN_OR_RETURN(bool row, q->Step());
  nlohmann::json extent = nullptr;
  if (row && !q->ColumnIsNull(0)) {
    extent = nlohmann::json::array();
    for (int i = 0; i < 6; ++i) extent.push_back(q->ColumnDouble(i));
  }
  q->Reset();
  return extent;
}

// A surface's description: the same fields as `tinbase info --json`, plus the store's CRS.
Result<nlohmann::json> DescribeSurface(Store& store, const SurfaceInfo& s) {
  TB_ASSIGN_OR_RETURN(SurfaceCounts c, SurfaceStore(store).Count(s));
  TB_ASSIGN_OR_RETURN(std::optional<Crs> crs, store.GetCrs());
  nlohmann::json j = {{"name", s.name},
                      {"kind", SurfaceKindName(s.kind)},
                      {"method", s.method},
                      {"vertices", c.vertices},
                      {"triangles", c.triangles},
                      {"visible_triangles", c.visible_triangles},
                      {"constraints", c.constraints},
                      {"features", c.features}};
  j["tolerance"] = s.tolerance ? nlohmann::json(*s.tolerance) : nlohmann::json(nullptr);
  j["crs"] = crs ? nlohmann::json(crs->Label()) : nlohmann::json(nullptr);
  TB_ASSIGN_OR_RETURN(j["extent"], SurfaceExtent(store, s));
  return j;
}

void ListSurfaces(ServiceContext& context, httplib::Response& res) {
  auto lease = context.stores().Reader();
  if (!lease.ok()) return ReplyStatus(res, lease.status());
  auto list = SurfaceStore(lease->store()).List();
  if (!list.ok()) return ReplyStatus(res, list.status());
  nlohmann::json out = nlohmann::json::array();
  for (const SurfaceInfo& s : *list) {
    auto j = DescribeSurface(lease->store(), s);
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
  auto j = DescribeSurface(lease->store(), *surface);
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
}

}  // namespace tinbase::service
