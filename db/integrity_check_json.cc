// The JSON of an integrity check.
#include "db/integrity_check_json.h"

#include <utility>

namespace tinbase {

nlohmann::json CheckJson(const std::vector<Problem>& problems) {
  nlohmann::json j = {{"ok", problems.empty()}, {"problems", nlohmann::json::array()}};
  for (const Problem& p : problems) {
    nlohmann::json row = {{"code", p.code}, {"surface", p.surface}, {"message", p.message}};
    row["triangle"] = p.triangle ? nlohmann::json(*p.triangle) : nlohmann::json(nullptr);
    j["problems"].push_back(std::move(row));
  }
  return j;
}

}  // namespace tinbase
