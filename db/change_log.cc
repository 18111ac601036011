#include "db/change_log.h"

#include <chrono>
#include <ctime>
#include <map>
#include <utility>
#include <vector>

#include "db/history/feature_versions.h"
#include "db/sql/settled_change.h"

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

namespace {

constexpr const char* kChangeColumns =
    "SELECT tx, time, surface, feature, action, removed, added, min_x, min_y, max_x, max_y "
    "FROM changes ";

Change ChangeOfRow(const Statement& stmt) {
  Change c;
  c.tx = stmt.ColumnInt(0);
  c.time = stmt.ColumnText(1);
  if (!stmt.ColumnIsNull(2)) c.surface = stmt.ColumnInt(2);
  if (!stmt.ColumnIsNull(3)) c.feature = stmt.ColumnInt(3);
  c.action = stmt.ColumnText(4);
  c.removed = stmt.ColumnInt(5);
  c.added = stmt.ColumnInt(6);
  c.min_x = stmt.ColumnDouble(7);
  c.min_y = stmt.ColumnDouble(8);
  c.max_x = stmt.ColumnDouble(9);
  c.max_y = stmt.ColumnDouble(10);
  return c;
}

}  // namespace

Result<std::vector<Change>> ChangesSince(Store& store, int64_t since) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached(std::string(kChangeColumns) + "WHERE tx > ? ORDER BY tx"));
  stmt->Bind(1, since);
  std::vector<Change> out;
  while (true) {
    auto row = stmt->Step();
    if (!row.ok()) {
      stmt->Reset();
      return row.status();
    }
    if (!*row) break;
    out.push_back(ChangeOfRow(*stmt));
  }
  stmt->Reset();
  TB_ASSIGN_OR_RETURN(auto touched, FeaturesTouchedSince(store, since));
  for (Change& c : out) {
    auto it = touched.find(c.tx);
    if (it != touched.end()) c.features = std::move(it->second);
  }
  return out;
}

int64_t SettledThrough(int64_t since, const std::vector<Change>& changes, int64_t settled) {
  int64_t mark = since;
  for (const Change& c : changes) {
    // The numbers between mark and c.tx were not seen: rolled back if at most `settled`, else
    // perhaps still to commit.
    if (c.tx != mark + 1 && c.tx - 1 > settled) break;
    mark = c.tx;
  }
  return mark;
}

Result<std::vector<Change>> SettledChangesSince(Store& store, int64_t since) {
  TB_ASSIGN_OR_RETURN(const int64_t settled, SettledChange(store.db()));
  TB_ASSIGN_OR_RETURN(std::vector<Change> changes, ChangesSince(store, since));
  const int64_t mark = SettledThrough(since, changes, settled);
  std::erase_if(changes, [mark](const Change& c) { return c.tx > mark; });
  return changes;
}

Result<int64_t> SettledLastTransaction(Store& store) {
  TB_ASSIGN_OR_RETURN(const int64_t settled, SettledChange(store.db()));
  TB_ASSIGN_OR_RETURN(const int64_t last, LastTransaction(store));
  if (last <= settled) return last;
  // The first seen number at or above `settled` whose successor is not seen (`settled` itself
  // standing for all below it).
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      store.db().Cached(
          "SELECT min(t) FROM (SELECT CAST(? AS BIGINT) AS t UNION ALL SELECT tx FROM changes "
          "WHERE tx > ?) seen WHERE NOT EXISTS (SELECT 1 FROM changes c "
          "WHERE c.tx = seen.t + 1)"));
  stmt->Bind(1, settled).Bind(2, settled);
  TB_ASSIGN_OR_RETURN(const bool row, stmt->Step());
  const int64_t mark = row && !stmt->ColumnIsNull(0) ? stmt->ColumnInt(0) : settled;
  stmt->Reset();
  return mark;
}

Result<int64_t> ChangeCount(Store& store) {
  return store.db().QueryInt("SELECT count(*) FROM changes");
}

Result<Change> ChangeOf(Store& store, int64_t tx) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached(std::string(kChangeColumns) + "WHERE tx = ?"));
  stmt->Bind(1, tx);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  if (!row) {
    stmt->Reset();
    return Status::NotFound(std::string("no transaction ") + std::to_string(tx));
  }
  Change c = ChangeOfRow(*stmt);
  stmt->Reset();
  TB_ASSIGN_OR_RETURN(c.features, FeaturesTouchedBy(store, tx));
  return c;
}

Result<int64_t> LastTransaction(Store& store) {
  TB_ASSIGN_OR_RETURN(Statement * stmt, store.db().Cached("SELECT max(tx) FROM changes"));
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  const int64_t last = row && !stmt->ColumnIsNull(0) ? stmt->ColumnInt(0) : 0;
  stmt->Reset();
  return last;
}

namespace {

// The first change `stmt` selects (kChangeColumns, parameters bound), without its features.
Result<std::optional<Change>> FirstOf(Statement& stmt) {
  TB_ASSIGN_OR_RETURN(bool row, stmt.Step());
  std::optional<Change> out;
  if (row) out = ChangeOfRow(stmt);
  stmt.Reset();
  return out;
}

}  // namespace

Result<std::optional<Change>> FirstChangeOfSurface(Store& store, int64_t surface) {
  TB_ASSIGN_OR_RETURN(Statement * stmt, store.db().Cached(std::string(kChangeColumns) +
                                                          "WHERE surface = ? ORDER BY tx LIMIT 1"));
  stmt->Bind(1, surface);
  return FirstOf(*stmt);
}

Result<std::optional<Change>> FirstChangeWithoutFeatures(Store& store, int64_t surface,
                                                         int64_t after) {
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      store.db().Cached(std::string(kChangeColumns) +
                        "WHERE surface = ? AND tx > ? AND NOT EXISTS (SELECT 1 FROM "
                        "feature_versions v WHERE v.tx = changes.tx) ORDER BY tx LIMIT 1"));
  stmt->Bind(1, surface).Bind(2, after);
  return FirstOf(*stmt);
}

}  // namespace tinbase
