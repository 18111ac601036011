#include "db/sql/connection.h"

#include <algorithm>

#include "db/postgres/pg_connection.h"
#include "db/sql/store_url.h"
#include "db/sqlite/sqlite_connection.h"

namespace tinbase {

// The one place that knows which backends exist (db/sql/store_url.h says how a target names one);
// nothing above the seam changes with the backend.
Result<std::unique_ptr<Connection>> Connection::Open(const std::string& target, Mode mode) {
  TB_ASSIGN_OR_RETURN(StoreUrl url, ParseStoreUrl(target));
  if (url.backend == Backend::kPostgres) {
    TB_ASSIGN_OR_RETURN(auto connection,
                        PgConnection::Open(url.pg_conninfo, url.pg_schema, url.label, mode));
    return std::unique_ptr<Connection>(std::move(connection));
  }
  TB_ASSIGN_OR_RETURN(auto connection, SqliteConnection::Open(url.sqlite_path, mode));
  return std::unique_ptr<Connection>(std::move(connection));
}

Result<int64_t> RunReturningId(Statement& insert) {
  Result<bool> row = insert.Step();
  if (!row.ok()) {
    insert.Reset();
    return row.status();
  }
  if (!*row) {
    insert.Reset();
    return Status::NotFound("no row written by " + insert.sql().substr(0, 60));
  }
  const int64_t id = insert.ColumnInt(0);
  insert.Reset();
  return id;
}

Result<int64_t> Connection::QueryInt(std::string_view sql) {
  TB_ASSIGN_OR_RETURN(Statement * stmt, Cached(sql));
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  if (!row) return Status::NotFound(std::string("no row for ") + std::string(sql));
  const int64_t v = stmt->ColumnInt(0);
  stmt->Reset();
  return v;
}

Result<int64_t> Connection::ReserveIds(std::string_view table, int64_t count) {
  if (backend() == Backend::kPostgres) {
    // The table's sequence, a run of `count` numbers at once (tinbase_reserve_ids, migration
    // 0017); `table` is one of the store's own, named by the code, never by input.
    TB_ASSIGN_OR_RETURN(Statement * reserve, Cached("SELECT tinbase_reserve_ids(?::regclass, ?)"));
    reserve->Bind(1, std::string(table) + "_id_seq").Bind(2, std::max<int64_t>(count, 1));
    TB_ASSIGN_OR_RETURN(bool row, reserve->Step());
    const int64_t first = row ? reserve->ColumnInt(0) : 0;
    reserve->Reset();
    if (!row) return Status::Corruption("no id reserved for " + std::string(table));
    return first;
  }
  TB_ASSIGN_OR_RETURN(int64_t largest,
                      QueryInt("SELECT coalesce(max(id), 0) FROM " + std::string(table)));
  return largest + 1;
}

Status Connection::LockRegion(int64_t /*surface*/, const std::vector<int64_t>& /*blocks*/,
                              bool /*whole_surface*/) {
  return Status::Ok();
}

}  // namespace tinbase
