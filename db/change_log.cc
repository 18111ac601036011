#include "db/change_log.h"

#include <chrono>
#include <ctime>

namespace tinbase {

namespace {
std::string UtcNow() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}
}  // namespace

Result<int64_t> AppendChange(Store& store, const Change& change) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("INSERT INTO changes(time, surface, feature, action, "
                                        "removed, added, min_x, min_y, max_x, max_y) "
                                        "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?) RETURNING tx"));
  stmt->Bind(1, UtcNow());
  if (change.surface)
    stmt->Bind(2, *change.surface);
  else
    stmt->BindNull(2);
  if (change.feature)
    stmt->Bind(3, *change.feature);
  else
    stmt->BindNull(3);
  stmt->Bind(4, change.action).Bind(5, change.removed).Bind(6, change.added);
  stmt->Bind(7, change.min_x).Bind(8, change.min_y).Bind(9, change.max_x).Bind(10, change.max_y);
  return RunReturningId(*stmt);
}

Result<std::vector<Change>> ChangesSince(Store& store, int64_t since) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("SELECT tx, time, surface, feature, action, removed, "
                                        "added, min_x, min_y, max_x, max_y FROM changes "
                                        "WHERE tx > ? ORDER BY tx"));
  stmt->Bind(1, since);
  std::vector<Change> out;
  while (true) {
    TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
    if (!row) break;
    Change c;
    c.tx = stmt->ColumnInt(0);
    c.time = stmt->ColumnText(1);
    if (!stmt->ColumnIsNull(2)) c.surface = stmt->ColumnInt(2);
    if (!stmt->ColumnIsNull(3)) c.feature = stmt->ColumnInt(3);
    c.action = stmt->ColumnText(4);
    c.removed = stmt->ColumnInt(5);
    c.added = stmt->ColumnInt(6);
    c.min_x = stmt->ColumnDouble(7);
    c.min_y = stmt->ColumnDouble(8);
    c.max_x = stmt->ColumnDouble(9);
    c.max_y = stmt->ColumnDouble(10);
    out.push_back(std::move(c));
  }
  stmt->Reset();
  return out;
}

}  // namespace tinbase
