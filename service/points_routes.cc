// The survey point routes: a body read into PointsAddOptions::points, or a feature id checked
// against the path's surface, then one AddPoints or RemovePoints call on the writer with the tile
// update as its before-commit hook.
#include "service/points_routes.h"

#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/vector/gdal_session.h"
#include "db/edit/mass_points.h"
#include "db/tiles/tiles_with_edit.h"
#include "service/crs_box.h"
#include "service/edit_request.h"
#include "service/geojson_request.h"
#include "service/json_reply.h"
#include "service/request_params.h"

namespace tinbase::service {

namespace {

// The points of the body in the store's CRS (from the query's crs when given), for `surface`,
// tagged by the query's tag. Read through a reader before the writer is taken.
Result<PointsAddOptions> PlanAdd(ServiceContext& context, const httplib::Request& req) {
  TB_ASSIGN_OR_RETURN(StoreLease reader, context.stores().Reader());
  TB_ASSIGN_OR_RETURN(SurfaceInfo surface, SurfaceFromPath(reader.store(), req));
  PointsAddOptions options;
  options.surface = surface.name;
  if (auto tag = OptionalParam(req, "tag")) options.tag = *tag;
  std::optional<Crs> source;
  if (auto crs = OptionalParam(req, "crs")) {
    QuietGdalErrors quiet;  // the message goes back to the client, not to the server's stderr
    TB_ASSIGN_OR_RETURN(source, ClientCrs(*crs, "parameter 'crs'"));
  }
  TB_ASSIGN_OR_RETURN(std::optional<Crs> store_crs, reader.store().GetCrs());
  if (!store_crs) return Status::InvalidArgument("the store has no CRS yet: import a DEM first");
  TB_ASSIGN_OR_RETURN(SurveyPointsBody body, ParseGeoJsonPoints(req.body, source, *store_crs));
  options.points = std::move(body.points);
  options.labels = std::move(body.labels);
  return options;
}

// The feature of DELETE /surfaces/{s}/points/{id}, checked to be the surface's.
Result<PointsRemoveOptions> PlanRemove(ServiceContext& context, const httplib::Request& req) {
  TB_ASSIGN_OR_RETURN(StoreLease reader, context.stores().Reader());
  TB_ASSIGN_OR_RETURN(SurfaceInfo surface, SurfaceFromPath(reader.store(), req));
  PointsRemoveOptions options;
  TB_ASSIGN_OR_RETURN(const int64_t id, IntegerPathPart(req, 2, "feature id", 1,
                                                        std::numeric_limits<int64_t>::max()));
  TB_RETURN_IF_ERROR(CheckFeatureOf(reader.store(), surface, id));
  options.feature = id;
  return options;
}

// {"tx", "features", "removed_features", "points_in", "vertices", "snapped", "bbox",
// "bbox_lonlat", "removed", "added", "tiles_updated"} of a committed points edit.
Result<nlohmann::json> Answer(Store& store, const PointsReport& report, int64_t tiles) {
  TB_ASSIGN_OR_RETURN(nlohmann::json change, DescribeCommittedChange(store, report.tx));
  return nlohmann::json{{"tx", report.tx},
                        {"features", report.features_added},
                        {"removed_features", report.features_removed},
                        {"points_in", report.points_in},
                        {"vertices", report.inserted},
                        {"snapped", report.snapped},
                        {"bbox", change["bbox"]},
                        {"bbox_lonlat", change["bbox_lonlat"]},
                        {"removed", report.removed},
                        {"added", report.added},
                        {"tiles_updated", tiles}};
}

// Runs `edit(store, before_commit)` on the writer with the tile update as its hook, then answers
// with `status` and wakes the change feed.
template <typename Edit>
void RunOnWriter(ServiceContext& context, httplib::Response& res, int status, const Edit& edit) {
  Result<nlohmann::json> answer = nlohmann::json();
  int64_t tx = 0;
  TileUpdates tiles;
  {
    auto writer = context.stores().Writer();
    if (!writer.ok()) return ReplyStatus(res, writer.status());
    Result<PointsReport> report = edit(writer->store(), UpdateTilesBeforeCommit(&tiles));
    if (!report.ok()) return ReplyStatus(res, report.status());
    tx = report->tx;
    answer = Answer(writer->store(), *report, TilesTouched(tiles));
  }
  context.changes().Notify(tx);  // the tiles committed with the edit
  if (!answer.ok()) return ReplyStatus(res, answer.status());
  ReplyJson(res, *answer, status);
}

void Add(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  if (!context.AllowWrite(req, res) || !JsonBody(req, res)) return;
  auto plan = PlanAdd(context, req);
  if (!plan.ok()) return ReplyStatus(res, plan.status());
  RunOnWriter(context, res, 201, [&](Store& store, BeforeCommit hook) {
    plan->before_commit = std::move(hook);
    return AddPoints(store, *plan);
  });
}

void Remove(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  if (!context.AllowWrite(req, res)) return;
  auto plan = PlanRemove(context, req);
  if (!plan.ok()) return ReplyStatus(res, plan.status());
  RunOnWriter(context, res, 200, [&](Store& store, BeforeCommit hook) {
    plan->before_commit = std::move(hook);
    return RemovePoints(store, *plan);
  });
}

}  // namespace

void RegisterPointsRoutes(httplib::Server& server, ServiceContext& context) {
  server.Post(
      R"(/surfaces/([^/]+)/points)",
      [&context](const httplib::Request& req, httplib::Response& res) { Add(context, req, res); });
  server.Delete(R"(/surfaces/([^/]+)/points/([^/]+))",
                [&context](const httplib::Request& req, httplib::Response& res) {
                  Remove(context, req, res);
                });
}

}  // namespace tinbase::service
