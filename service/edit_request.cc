// The write routes' shared checks and the description of their change.
#include "service/edit_request.h"

#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "db/change_log.h"
#include "service/change_json.h"
#include "service/json_reply.h"

namespace tinbase::service {

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

Result<nlohmann::json> DescribeCommittedChange(Store& store, int64_t tx) {
  TB_ASSIGN_OR_RETURN(ChangeJson describe, ChangeJson::For(store));
  TB_ASSIGN_OR_RETURN(std::vector<Change> changes, ChangesSince(store, tx - 1));
  if (changes.empty() || changes.front().tx != tx)
    return Status::Corruption("change " + std::to_string(tx) + " is not in the log");
  return describe.Describe(store, changes.front());
}

}  // namespace tinbase::service
