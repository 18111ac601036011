// GET /surfaces/{s}/profile?line=x1,y1,x2,y2,...[&crs=]: the section of db/query/profile.h;
// GET /surfaces/{s}/measures/area|volume|slope?[bbox=&feature=&tag=]: the measures of
// core/measure/ over the visible part of the selection (level= for volume). Each answers the
// JSON `tinbase profile --json` / `tinbase measure ... --json` prints (db/query/profile_json.h,
// db/query/measure_json.h); slope gathers the CLI's per-triangle lines into "triangles".
#include <nlohmann/json.hpp>

#include "core/measure/slope_aspect.h"
#include "core/measure/surface_area.h"
#include "core/measure/volume.h"
#include "db/query/measure_json.h"
#include "db/query/measure_source.h"
#include "db/query/profile.h"
#include "db/query/profile_json.h"
#include "service/client_crs.h"
#include "service/json_reply.h"
#include "service/request_params.h"
#include "service/surface_read.h"
#include "service/surface_route_parts.h"

namespace tinbase::service {

namespace {

void Profile(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto line = LineParam(req, "line");
  if (!line.ok()) return ReplyStatus(res, line.status());
  auto client = CrsParam(req);
  if (!client.ok()) return ReplyStatus(res, client.status());
  auto read = BeginSurfaceRead(context, req);
  if (!read.ok()) return ReplyStatus(res, read.status());
  auto moved = PointsToStore(read->crs, *client, std::move(*line));
  if (!moved.ok()) return ReplyStatus(res, moved.status());
  auto profile = ProfileAlong(read->store(), read->surface, *moved);
  if (!profile.ok()) return ReplyStatus(res, profile.status());
  ReplyJsonWithin(res, ProfileJson(*profile, read->surface.name),
                  context.options().max_result_bytes);
}

// The measure's selection (bbox=, feature=, tag=; visible triangles only) of the path's surface.
Result<MeasureSource> MeasureSourceOf(SurfaceRead& read, const httplib::Request& req) {
  TB_ASSIGN_OR_RETURN(SurfaceFilter filter, FilterParams(req));
  return LoadMeasureSource(read.store(), read.surface.name, filter);
}

void Area(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto read = BeginSurfaceRead(context, req);
  if (!read.ok()) return ReplyStatus(res, read.status());
  auto source = MeasureSourceOf(*read, req);
  if (!source.ok()) return ReplyStatus(res, source.status());
  ReplyJson(res, AreaJson(*source, MeasureArea(source->part.tin, source->frame)));
}

void Volume(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto level = FiniteParam(req, "level");
  if (!level.ok()) return ReplyStatus(res, level.status());
  auto read = BeginSurfaceRead(context, req);
  if (!read.ok()) return ReplyStatus(res, read.status());
  auto source = MeasureSourceOf(*read, req);
  if (!source.ok()) return ReplyStatus(res, source.status());
  auto volume = VolumeAgainstLevel(source->part.tin, *level, source->frame);
  if (!volume.ok())
    return ReplyStatus(res, volume.status().WithContext("surface '" + source->surface.name + "'"));
  ReplyJson(res, VolumeJson(*source, *level, false, *volume));
}

void Slope(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto read = BeginSurfaceRead(context, req);
  if (!read.ok()) return ReplyStatus(res, read.status());
  auto source = MeasureSourceOf(*read, req);
  if (!source.ok()) return ReplyStatus(res, source.status());
  nlohmann::json triangles = nlohmann::json::array();
  for (const TriangleSlope& s : SlopeAndAspect(source->part.tin, source->frame, true))
    triangles.push_back(SlopeJson(*source, s));
  ReplyJsonWithin(res, {{"surface", source->surface.name}, {"triangles", std::move(triangles)}},
                  context.options().max_result_bytes);
}

}  // namespace

void RegisterMeasureRoutes(httplib::Server& server, ServiceContext& context) {
  server.Get(R"(/surfaces/([^/]+)/profile)",
             [&context](const httplib::Request& req, httplib::Response& res) {
               Profile(context, req, res);
             });
  server.Get(
      R"(/surfaces/([^/]+)/measures/area)",
      [&context](const httplib::Request& req, httplib::Response& res) { Area(context, req, res); });
  server.Get(R"(/surfaces/([^/]+)/measures/volume)",
             [&context](const httplib::Request& req, httplib::Response& res) {
               Volume(context, req, res);
             });
  server.Get(R"(/surfaces/([^/]+)/measures/slope)",
             [&context](const httplib::Request& req, httplib::Response& res) {
               Slope(context, req, res);
             });
}

}  // namespace tinbase::service
