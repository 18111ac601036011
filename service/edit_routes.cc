// The edit routes: features posted, replaced and removed through the same transactional engine
// as `tinbase polygon add|update|remove` (db/polygon_editor.h), with the tile pyramids brought up
// to date inside the edit's own transaction: the edit and its tiles commit together, or neither
// does. The body is parsed and checked before the writer is taken, so a bad request never holds
// up other writes.
#include <algorithm>
#include <cctype>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/vector/gdal_session.h"
#include "db/change_log.h"
#include "db/polygon_editor.h"
#include "db/tiles/tile_pyramid.h"
#include "service/change_json.h"
#include "service/crs_box.h"
#include "service/geojson_request.h"
#include "service/json_reply.h"
#include "service/request_params.h"
#include "service/routes.h"

namespace tinbase::service {

namespace {

enum class EditKind { kAdd, kReplace, kRemove };

// Whether the body is declared JSON (application/json or application/geo+json, any parameters);
// answers 415 otherwise.
bool JsonBody(const httplib::Request& req, httplib::Response& res) {
  std::string type = req.get_header_value("Content-Type");
  type = type.substr(0, type.find(';'));
  std::erase_if(type, [](unsigned char c) { return std::isspace(c) != 0; });
  std::transform(type.begin(), type.end(), type.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (type == "application/json" || type == "application/geo+json") return true;
  ReplyError(res, 415, "unsupported_media_type",
             "the body must be GeoJSON sent as application/json or application/geo+json, not '" +
                 req.get_header_value("Content-Type") + "'");
  return false;
}

// NotFound unless feature `id` exists and belongs to `surface`.
Status CheckFeatureOf(Store& store, const SurfaceInfo& surface, int64_t id) {
  TB_ASSIGN_OR_RETURN(Statement * q,
                      store.db().Cached("SELECT surface FROM features WHERE id = ?"));
  q->Bind(1, id);
  TB_ASSIGN_OR_RETURN(bool row, q->Step());
  const bool ours = row && q->ColumnInt(0) == surface.id;
  q->Reset();
  if (!ours)
    return Status::NotFound("no feature " + std::to_string(id) + " in surface '" + surface.name +
                            "'");
  return Status::Ok();
}

// The editor's options from the query (mode, tag, level, crs) and the GeoJSON body.
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

// Brings every tile pyramid up to date inside the edit's transaction (PolygonAddOptions::
// before_commit), counting the tiles rewritten or deleted into `*tiles`: the edit and its tiles
// commit together, so a reader's snapshot never holds an edit with tiles that predate it. A
// failed update rolls the edit back.
BeforeCommit UpdateTilesWithEdit(int64_t* tiles) {
  return [tiles](Store& store, int64_t /*tx*/) -> Status {
    auto updated = UpdateAllTilePyramids(store);
    if (!updated.ok()) return updated.status().WithContext("updating the tiles of the edit");
    *tiles = 0;
    for (const auto& [surface, report] : *updated)
      *tiles += report.tiles_rewritten + report.tiles_deleted;
    return Status::Ok();
  };
}

// {"tx", "features", "removed_features", "bbox", "bbox_lonlat", "change", "tiles_updated"} of a
// committed edit.
Result<nlohmann::json> Answer(Store& store, const PolygonAddReport& report, int64_t removed,
                              int64_t tiles) {
  TB_ASSIGN_OR_RETURN(ChangeJson describe, ChangeJson::For(store));
  TB_ASSIGN_OR_RETURN(std::vector<Change> changes, ChangesSince(store, report.tx - 1));
  if (changes.empty() || changes.front().tx != report.tx)
    return Status::Corruption("change " + std::to_string(report.tx) + " is not in the log");
  TB_ASSIGN_OR_RETURN(nlohmann::json change, describe.Describe(store, changes.front()));
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
  int64_t tiles = 0;
  plan->options.before_commit = UpdateTilesWithEdit(&tiles);
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
    answer = Answer(writer->store(), *report, kind == EditKind::kAdd ? 0 : plan->feature, tiles);
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
}

}  // namespace tinbase::service
