// GET /surfaces/{s}/locate?x=&y= (or lon=&lat=, or x=&y=&crs=): the triangle holding one point
// and z there; POST /surfaces/{s}/locate {"points": [[x, y], ...], "crs"?}: the triangle, z and
// tag under each of many points, in input order (db/query/bulk_locate.h).
#include <cmath>
#include <nlohmann/json.hpp>

#include "db/point_locator.h"
#include "db/query/bulk_locate.h"
#include "service/client_crs.h"
#include "service/json_reply.h"
#include "service/request_params.h"
#include "service/surface_read.h"
#include "service/surface_route_parts.h"
#include "service/triangle_json.h"

namespace tinbase::service {

namespace {

// The point of a GET: x, y (in crs= or the store's CRS) or lon, lat; moved into the store's CRS.
Result<Point2> QueryPoint(const httplib::Request& req, const StoreCrs* store_crs) {
  const bool lonlat = req.has_param("lon") || req.has_param("lat");
  if (lonlat && (req.has_param("x") || req.has_param("y") || req.has_param("crs")))
    return Status::InvalidArgument("give x and y (with crs= or not), or lon and lat, not both");
  std::optional<Crs> client;
  Point2 p;
  if (lonlat) {
    TB_ASSIGN_OR_RETURN(p.x, FiniteParam(req, "lon"));
    TB_ASSIGN_OR_RETURN(p.y, FiniteParam(req, "lat"));
    TB_ASSIGN_OR_RETURN(client, LonLatCrs());
  } else {
    TB_ASSIGN_OR_RETURN(p.x, FiniteParam(req, "x"));
    TB_ASSIGN_OR_RETURN(p.y, FiniteParam(req, "y"));
    TB_ASSIGN_OR_RETURN(client, CrsParam(req));
  }
  TB_ASSIGN_OR_RETURN(std::vector<Point2> moved, PointsToStore(store_crs, client, {p}));
  return moved[0];
}

void LocateOne(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto read = BeginSurfaceRead(context, req);
  if (!read.ok()) return ReplyStatus(res, read.status());
  auto p = QueryPoint(req, read->crs);
  if (!p.ok()) return ReplyStatus(res, p.status());
  auto where = LocatePoint(read->store(), read->surface, p->x, p->y);
  if (!where.ok()) {
    if (where.status().code() == StatusCode::kNotFound)
      return ReplyError(res, 404, "outside", where.status().message());
    return ReplyStatus(res, where.status());
  }
  auto triangle = NeighboursOf(read->store(), read->surface, where->triangle);
  if (!triangle.ok()) return ReplyStatus(res, triangle.status());
  auto t = TrianglesJson({ViewOf(*triangle)}, read->crs);
  if (!t.ok()) return ReplyStatus(res, t.status());
  ReplyJson(res, {{"x", p->x}, {"y", p->y}, {"triangle", (*t)[0]}, {"z", where->z}});
}

// One number of the body: points[i][k], finite.
Result<double> BodyNumber(const nlohmann::json& v, size_t i, int k) {
  if (!v.is_number())
    return Status::InvalidArgument("points[" + std::to_string(i) + "][" + std::to_string(k) +
                                   "] is not a number");
  const double d = v.get<double>();
  if (!std::isfinite(d))
    return Status::InvalidArgument("points[" + std::to_string(i) + "][" + std::to_string(k) +
                                   "] is not finite");
  return d;
}

struct LocateBody {
  std::vector<Point2> points;
  std::optional<Crs> crs;
};

// {"points": [[x, y], ...], "crs": "EPSG:4326"?}, every element checked and named when bad.
Result<LocateBody> ParseLocateBody(const std::string& text) {
  nlohmann::json body;
  try {
    body = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for 1e999
    // e.what() names the byte and what was wrong there.
    return Status::InvalidArgument(std::string("the body is not JSON: ") + e.what());
  }
  if (!body.is_object() || !body.contains("points") || !body["points"].is_array())
    return Status::InvalidArgument("the body needs \"points\": [[x, y], ...]");
  LocateBody out;
  const nlohmann::json& points = body["points"];
  out.points.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const nlohmann::json& p = points[i];
    if (!p.is_array() || p.size() != 2)
      return Status::InvalidArgument("points[" + std::to_string(i) + "] is not [x, y]");
    Point2 q;
    TB_ASSIGN_OR_RETURN(q.x, BodyNumber(p[0], i, 0));
    TB_ASSIGN_OR_RETURN(q.y, BodyNumber(p[1], i, 1));
    out.points.push_back(q);
  }
  if (body.contains("crs")) {
    if (!body["crs"].is_string()) return Status::InvalidArgument("\"crs\" is not a string");
    auto crs = Crs::FromUserInput(body["crs"].get<std::string>());
    if (!crs.ok())
      return Status::InvalidArgument("\"crs\": '" + body["crs"].get<std::string>() +
                                     "' is not a coordinate system GDAL knows");
    out.crs = std::move(*crs);
  }
  return out;
}

bool IsJsonContent(const httplib::Request& req) {
  const std::string type = req.get_header_value("Content-Type");
  return type.rfind("application/json", 0) == 0;
}

void LocateMany(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  if (!IsJsonContent(req))
    return ReplyError(res, 415, "unsupported_media_type",
                      "POST locate takes Content-Type application/json, got '" +
                          req.get_header_value("Content-Type") + "'");
  auto body = ParseLocateBody(req.body);
  if (!body.ok()) return ReplyStatus(res, body.status());
  auto read = BeginSurfaceRead(context, req);
  if (!read.ok()) return ReplyStatus(res, read.status());
  auto points = PointsToStore(read->crs, body->crs, std::move(body->points));
  if (!points.ok()) return ReplyStatus(res, points.status());
  nlohmann::json results = nlohmann::json::array();
  Status s = LocatePoints(
      read->store(), read->surface, *points, [&](size_t, const Point2& p, const Location* where) {
        nlohmann::json j = {
            {"x", p.x}, {"y", p.y}, {"triangle", nullptr}, {"z", nullptr}, {"tag", nullptr}};
        if (where != nullptr) {
          j["triangle"] = where->triangle;
          j["z"] = where->z;
          if (where->tag) j["tag"] = *where->tag;
        }
        results.push_back(std::move(j));
        return Status::Ok();
      });
  if (!s.ok()) return ReplyStatus(res, s);
  ReplyJsonWithin(res, {{"results", results}}, context.options().max_result_bytes);
}

}  // namespace

void RegisterLocateRoutes(httplib::Server& server, ServiceContext& context) {
  server.Get(R"(/surfaces/([^/]+)/locate)",
             [&context](const httplib::Request& req, httplib::Response& res) {
               LocateOne(context, req, res);
             });
  server.Post(R"(/surfaces/([^/]+)/locate)",
              [&context](const httplib::Request& req, httplib::Response& res) {
                LocateMany(context, req, res);
              });
}

}  // namespace tinbase::service
