#include "db/edit/constraint_kinds.h"

#include <algorithm>

namespace tinbase {

namespace {

// The softline features among `features` (sorted, unique).
Result<std::vector<int64_t>> SoftlinesAmong(Connection& db, const std::vector<int64_t>& features) {
  TB_ASSIGN_OR_RETURN(Statement * mode,
                      db.Cached("SELECT 1 FROM features WHERE id = ? AND mode = 'softline'"));
  std::vector<int64_t> soft;
  for (int64_t f : features) {
    mode->Bind(1, f);
    TB_ASSIGN_OR_RETURN(bool row, mode->Step());
    mode->Reset();
    if (row) soft.push_back(f);
  }
  return soft;
}

}  // namespace

Status MarkSoftConstraints(Connection& db, int64_t surface,
                           const std::vector<std::pair<MeshEdge, int64_t>>& added) {
  std::vector<int64_t> owners;
  for (const auto& [edge, feature] : added)
    if (feature != 0) owners.push_back(feature);
  std::sort(owners.begin(), owners.end());
  owners.erase(std::unique(owners.begin(), owners.end()), owners.end());
  TB_ASSIGN_OR_RETURN(std::vector<int64_t> soft, SoftlinesAmong(db, owners));
  if (soft.empty()) return Status::Ok();
  TB_ASSIGN_OR_RETURN(Statement * update,
                      db.Cached("UPDATE constraints SET kind = 'soft' WHERE surface = ? AND "
                                "va = ? AND vb = ? AND feature = ?"));
  for (const auto& [edge, feature] : added) {
    if (!std::binary_search(soft.begin(), soft.end(), feature)) continue;
    update->Bind(1, surface).Bind(2, edge.first).Bind(3, edge.second).Bind(4, feature);
    TB_RETURN_IF_ERROR(update->Run());
  }
  return Status::Ok();
}

}  // namespace tinbase
