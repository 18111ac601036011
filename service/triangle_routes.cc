// GET /surfaces/{s}/triangles/{id}: a triangle and its three neighbours (db/query/topology.h);
// GET /surfaces/{s}/triangles?bbox=&limit=: the triangles meeting a window
// (db/query/surface_selection.h), 413 when there are more than `limit`.
#include <limits>
#include <nlohmann/json.hpp>

#include "db/query/surface_selection.h"
#include "db/query/topology.h"
#include "service/json_reply.h"
#include "service/request_params.h"
#include "service/surface_read.h"
#include "service/surface_route_parts.h"
#include "service/triangle_json.h"

namespace tinbase::service {

namespace {

// Default and largest `limit` of a window's triangles: the viewer asks for a screenful, and the
// answer of the largest is a few hundred MiB of JSON, the order of max_result_bytes.
constexpr int64_t kDefaultTriangleLimit = 10000;
constexpr int64_t kMaxTriangleLimit = 1000000;

void OneTriangle(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto read = BeginSurfaceRead(context, req);
  if (!read.ok()) return ReplyStatus(res, read.status());
  auto id = IntegerPathPart(req, 2, "triangle id", 1, std::numeric_limits<int64_t>::max());
  if (!id.ok()) return ReplyStatus(res, id.status());
  auto triangle = NeighboursOf(read->store(), read->surface, *id);
  if (!triangle.ok()) return ReplyStatus(res, triangle.status());
  std::vector<TriangleView> views = {ViewOf(*triangle)};
  for (const SharedEdge& e : triangle->edges) {
    if (!e.neighbour) continue;
    auto n = NeighboursOf(read->store(), read->surface, *e.neighbour);
    if (!n.ok()) return ReplyStatus(res, n.status());
    views.push_back(ViewOf(*n));
  }
  auto json = TrianglesJson(views, read->crs);
  if (!json.ok()) return ReplyStatus(res, json.status());
  nlohmann::json neighbours = nlohmann::json::array();
  size_t next = 1;
  for (const SharedEdge& e : triangle->edges)
    neighbours.push_back(e.neighbour ? (*json)[next++] : nlohmann::json(nullptr));
  ReplyJson(res, {{"triangle", (*json)[0]}, {"neighbours", neighbours}});
}

void WindowTriangles(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto filter = FilterParams(req);
  if (!filter.ok()) return ReplyStatus(res, filter.status());
  if (!filter->bbox)
    return ReplyError(res, 400, "invalid_argument",
                      "missing parameter 'bbox' (minx,miny,maxx,maxy)");
  auto limit = IntegerParam(req, "limit", 1, kMaxTriangleLimit, kDefaultTriangleLimit);
  if (!limit.ok()) return ReplyStatus(res, limit.status());
  auto read = BeginSurfaceRead(context, req);
  if (!read.ok()) return ReplyStatus(res, read.status());
  auto selected = SelectSurface(read->store(), read->surface, *filter);
  if (!selected.ok()) {
    // An empty window is an empty answer, not a missing thing.
    if (selected.status().code() == StatusCode::kNotFound && filter->feature == 0)
      return ReplyJson(res, {{"triangles", nlohmann::json::array()}});
    return ReplyStatus(res, selected.status());
  }
  const size_t count = selected->tin.triangles.size();
  if (count > static_cast<size_t>(*limit))
    return ReplyError(res, 413, "too_many_triangles",
                      "the selection (" + filter->Describe() + ") holds " + std::to_string(count) +
                          " triangles, more than limit=" + std::to_string(*limit) + " (at most " +
                          std::to_string(kMaxTriangleLimit) + "); ask for a smaller bbox");
  auto views = ViewsOf(read->store(), read->surface, *selected);
  if (!views.ok()) return ReplyStatus(res, views.status());
  auto json = TrianglesJson(*views, read->crs);
  if (!json.ok()) return ReplyStatus(res, json.status());
  ReplyJsonWithin(res, {{"triangles", std::move(*json)}}, context.options().max_result_bytes);
}

}  // namespace

void RegisterTriangleRoutes(httplib::Server& server, ServiceContext& context) {
  server.Get(R"(/surfaces/([^/]+)/triangles/([^/]+))",
             [&context](const httplib::Request& req, httplib::Response& res) {
               OneTriangle(context, req, res);
             });
  server.Get(R"(/surfaces/([^/]+)/triangles)",
             [&context](const httplib::Request& req, httplib::Response& res) {
               WindowTriangles(context, req, res);
             });
}

}  // namespace tinbase::service
