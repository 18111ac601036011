#include "db/sql/connection.h"

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

}  // namespace tinbase
