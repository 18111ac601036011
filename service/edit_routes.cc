// The edit routes: features posted, replaced and removed through the same transactional engine
// as `tinbase polygon add|update|remove` (db/polygon_editor.h), with the tile pyramids brought up
// to date inside the edit's own transaction: the edit and its tiles commit together, or neither
// does. The body is parsed and checked before the writer is taken, so a bad request never holds
// up other writes.
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/vector/gdal_session.h"
#include "db/polygon_editor.h"
#include "db/tiles/tiles_with_edit.h"
#include "service/crs_box.h"
#include "service/edit_request.h"
#include "service/geojson_request.h"
#include "service/json_reply.h"
#include "service/points_routes.h"
#include "service/request_params.h"
#include "service/routes.h"

namespace tinbase::service {

namespace {

enum class EditKind { kAdd, kReplace, kRemove };

// The editor's options from the query (mode, tag, level, z_from, crs) and the GeoJSON body.
Result<PolygonAddOptions> ReadEditOptions(Store& store, const SurfaceInfo& surface,
                                          const httplib::Request& req) {
  PolygonAddOptions options;
  options.surface = surface.name;
  if (auto mode = OptionalParam(req, "mode")) {
    auto parsed = ParseFeatureMode(*mode);
    if (!parsed.ok()) return parsed.status().WithContext("parameter 'mode'");
    options.mode = *parsed;
  }
  if (auto tag = OptionalParam(req, "tag")) options.tag = *tag;
  if (OptionalParam(req, "level")) {
    TB_ASSIGN_OR_RETURN(options.level, FiniteParam(req, "level"));
  }
  if (auto z_from = OptionalParam(req, "z_from")) {
    auto parsed = ParseZFrom(*z_from);
    if (!parsed.ok()) return parsed.status().WithContext("parameter 'z_from'");
    options.z_from = *parsed;
    options.z_from_given = true;
  }
  std::optional<Crs> source;
  if (auto crs = OptionalParam(req, "crs")) {
    QuietGdalErrors quiet;  // the message goes back to the client, not to the server's stderr
    TB_ASSIGN_OR_RETURN(source, ClientCrs(*crs, "parameter 'crs'"));
  }
  TB_ASSIGN_OR_RETURN(std::optional<Crs> store_crs, store.GetCrs());
  if (!store_crs) return Status::InvalidArgument("the store has no CRS yet: import a DEM first");
  TB_ASSIGN_OR_RETURN(options.features, ParseGeoJsonFeatures(req.body, source, *store_crs));
  return options;
}

// What the edit needs, read through a reader before the writer is taken.
struct EditPlan {
  int64_t feature = 0;  // replace, remove
  PolygonAddOptions options;
};

Result<EditPlan> PlanEdit(ServiceContext& context, const httplib::Request& req, EditKind kind) {
  TB_ASSIGN_OR_RETURN(StoreLease reader, context.stores().Reader());
  TB_ASSIGN_OR_RETURN(SurfaceInfo surface, SurfaceFromPath(reader.store(), req));
  EditPlan plan;
  if (kind != EditKind::kAdd) {
    TB_ASSIGN_OR_RETURN(plan.feature, IntegerPathPart(req, 2, "feature id", 1,
                                                      std::numeric_limits<int64_t>::max()));
    TB_RETURN_IF_ERROR(CheckFeatureOf(reader.store(), surface, plan.feature));
  }
  if (kind != EditKind::kRemove) {
    TB_ASSIGN_OR_RETURN(plan.options, ReadEditOptions(reader.store(), surface, req));
  }
  return plan;
}

// {"tx", "features", "removed_features", "bbox", "bbox_lonlat", "change", "tiles_updated"} of a
// committed edit.
Result<nlohmann::json> Answer(Store& store, const PolygonAddReport& report, int64_t removed,
                              int64_t tiles) {
  TB_ASSIGN_OR_RETURN(nlohmann::json change, DescribeCommittedChange(store, report.tx));
  nlohmann::json answer = {{"tx", report.tx}, {"features", report.feature_ids}};
  answer["removed_features"] = removed != 0 ? nlohmann::json{removed} : nlohmann::json::array();
  answer["bbox"] = change["bbox"];
  answer["bbox_lonlat"] = change["bbox_lonlat"];
  answer["removed"] = report.removed;
  answer["added"] = report.added;
  answer["clipped"] = OverhangCutsJson(report.clipped);  // polygons cut to the data area
  answer["tiles_updated"] = tiles;
  return answer;
}

void Edit(ServiceContext& context, const httplib::Request& req, httplib::Response& res,
          EditKind kind) {
  if (!context.AllowWrite(req, res)) return;
  if (kind != EditKind::kRemove && !JsonBody(req, res)) return;
  auto plan = PlanEdit(context, req, kind);
  if (!plan.ok()) return ReplyStatus(res, plan.status());
  Result<nlohmann::json> answer = nlohmann::json();
  int64_t tx = 0;
  TileUpdates tiles;
  plan->options.before_commit = UpdateTilesBeforeCommit(&tiles);
  {
    auto writer = context.stores().Writer();
    if (!writer.ok()) return ReplyStatus(res, writer.status());
    Result<PolygonAddReport> report =
        kind == EditKind::kAdd ? AddPolygons(writer->store(), plan->options)
        : kind == EditKind::kReplace
            ? UpdatePolygon(writer->store(), plan->feature, plan->options)
            : RemovePolygon(writer->store(), plan->feature, plan->options.before_commit);
    if (!report.ok()) return ReplyStatus(res, report.status());
    tx = report->tx;
    answer = Answer(writer->store(), *report, kind == EditKind::kAdd ? 0 : plan->feature,
                    TilesTouched(tiles));
  }
  // The tiles committed with the edit: a client the feed wakes fetches tiles that show it.
  context.changes().Notify(tx);
  if (!answer.ok()) return ReplyStatus(res, answer.status());
  ReplyJson(res, *answer, kind == EditKind::kAdd ? 201 : 200);
}

}  // namespace

void RegisterEditRoutes(httplib::Server& server, ServiceContext& context) {
  server.Post(R"(/surfaces/([^/]+)/features)",
              [&context](const httplib::Request& req, httplib::Response& res) {
                Edit(context, req, res, EditKind::kAdd);
              });
  server.Put(R"(/surfaces/([^/]+)/features/([^/]+))",
             [&context](const httplib::Request& req, httplib::Response& res) {
               Edit(context, req, res, EditKind::kReplace);
             });
  server.Delete(R"(/surfaces/([^/]+)/features/([^/]+))",
                [&context](const httplib::Request& req, httplib::Response& res) {
                  Edit(context, req, res, EditKind::kRemove);
                });
  RegisterPointsRoutes(server, context);
}

}  // namespace tinbase::service
