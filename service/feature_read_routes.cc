// GET /surfaces/{s}/features[?crs=]: the surface's features as a GeoJSON FeatureCollection
// (polygons with closed rings, shells counter-clockwise and holes clockwise as RFC 7946 asks;
// breaklines as lines), each with its id, mode, tag, level and attributes as properties.
// GET /surfaces/{s}/tags: each tag with the number of its triangles (the viewer's legend).
#include <nlohmann/json.hpp>

#include "core/geometry/reproject.h"
#include "db/feature_store.h"
#include "service/client_crs.h"
#include "service/json_reply.h"
#include "service/request_params.h"
#include "service/surface_read.h"
#include "service/surface_route_parts.h"

namespace tinbase::service {

namespace {

// Every point of the feature, in the order RingJson and LineJson read them back.
void CollectPoints(const EditorFeature& f, std::vector<Point2>& out) {
  for (const Polygon& p : f.polygons) {
    out.insert(out.end(), p.shell.begin(), p.shell.end());
    for (const Ring& hole : p.holes) out.insert(out.end(), hole.begin(), hole.end());
  }
  for (const auto& line : f.lines) out.insert(out.end(), line.begin(), line.end());
}

// The next `n` points of `points` from `*next` as GeoJSON positions, closed when `close`.
nlohmann::json Positions(const std::vector<Point2>& points, size_t* next, size_t n, bool close) {
  nlohmann::json out = nlohmann::json::array();
  const size_t first = *next;
  for (size_t i = 0; i < n; ++i, ++*next) out.push_back({points[*next].x, points[*next].y});
  if (close && n > 0) out.push_back({points[first].x, points[first].y});
  return out;
}

nlohmann::json GeometryJson(const EditorFeature& f, const std::vector<Point2>& points,
                            size_t* next) {
  if (!f.polygons.empty()) {
    nlohmann::json polygons = nlohmann::json::array();
    for (const Polygon& p : f.polygons) {
      nlohmann::json rings = nlohmann::json::array();
      rings.push_back(Positions(points, next, p.shell.size(), true));
      for (const Ring& hole : p.holes) rings.push_back(Positions(points, next, hole.size(), true));
      polygons.push_back(std::move(rings));
    }
    if (polygons.size() == 1) return {{"type", "Polygon"}, {"coordinates", polygons[0]}};
    return {{"type", "MultiPolygon"}, {"coordinates", polygons}};
  }
  nlohmann::json lines = nlohmann::json::array();
  for (const auto& line : f.lines) lines.push_back(Positions(points, next, line.size(), false));
  if (lines.size() == 1) return {{"type", "LineString"}, {"coordinates", lines[0]}};
  return {{"type", "MultiLineString"}, {"coordinates", lines}};
}

nlohmann::json PropertiesJson(const EditorFeature& f) {
  nlohmann::json props = f.attributes.is_object() ? f.attributes : nlohmann::json::object();
  // The store's own fields win over attributes of the same name.
  props["id"] = f.id;
  props["mode"] = FeatureModeName(f.mode);
  props["tag"] = f.tag ? nlohmann::json(*f.tag) : nlohmann::json(nullptr);
  props["level"] = f.level ? nlohmann::json(*f.level) : nlohmann::json(nullptr);
  return props;
}

void Features(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto client = CrsParam(req);
  if (!client.ok()) return ReplyStatus(res, client.status());
  auto read = BeginSurfaceRead(context, req);
  if (!read.ok()) return ReplyStatus(res, read.status());
  if (*client && read->crs == nullptr)
    return ReplyError(
        res, 400, "invalid_argument",
        "the store has no CRS, so its features cannot be given in " + (*client)->Label());
  auto features = LoadFeatures(read->store(), read->surface);
  if (!features.ok()) return ReplyStatus(res, features.status());
  std::vector<Point2> points;
  for (const EditorFeature& f : *features) CollectPoints(f, points);
  if (*client) {
    std::vector<TinVertex> v(points.size());
    for (size_t i = 0; i < points.size(); ++i) v[i].x = points[i].x, v[i].y = points[i].y;
    if (Status s = ReprojectXy(read->crs->crs(), **client, v); !s.ok()) return ReplyStatus(res, s);
    for (size_t i = 0; i < points.size(); ++i) points[i] = {v[i].x, v[i].y};
  }
  nlohmann::json out = {{"type", "FeatureCollection"}, {"features", nlohmann::json::array()}};
  size_t next = 0;
  for (const EditorFeature& f : *features)
    out["features"].push_back({{"type", "Feature"},
                               {"id", f.id},
                               {"geometry", GeometryJson(f, points, &next)},
                               {"properties", PropertiesJson(f)}});
  ReplyJsonWithin(res, out, context.options().max_result_bytes, "application/geo+json");
}

void Tags(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto read = BeginSurfaceRead(context, req);
  if (!read.ok()) return ReplyStatus(res, read.status());
  auto q = read->store().db().Cached(
      "SELECT tags.value, count(*), sum(triangles.visible) FROM triangles "
      "JOIN tags ON tags.id = triangles.tag WHERE triangles.surface = ? "
      "GROUP BY tags.value ORDER BY tags.value");
  if (!q.ok()) return ReplyStatus(res, q.status());
  (*q)->Bind(1, read->surface.id);
  nlohmann::json tags = nlohmann::json::array();
  while (true) {
    auto row = (*q)->Step();
    if (!row.ok()) {
      (*q)->Reset();
      return ReplyStatus(res, row.status());
    }
    if (!*row) break;
    tags.push_back({{"tag", (*q)->ColumnText(0)},
                    {"triangles", (*q)->ColumnInt(1)},
                    {"visible_triangles", (*q)->ColumnInt(2)}});
  }
  (*q)->Reset();
  ReplyJsonWithin(res, {{"tags", tags}}, context.options().max_result_bytes);
}

}  // namespace

void RegisterFeatureReadRoutes(httplib::Server& server, ServiceContext& context) {
  server.Get(R"(/surfaces/([^/]+)/features)",
             [&context](const httplib::Request& req, httplib::Response& res) {
               Features(context, req, res);
             });
  server.Get(
      R"(/surfaces/([^/]+)/tags)",
      [&context](const httplib::Request& req, httplib::Response& res) { Tags(context, req, res); });
}

}  // namespace tinbase::service
