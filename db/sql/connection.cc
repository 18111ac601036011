#include "db/sql/connection.h"

#include "db/sqlite/sqlite_connection.h"

namespace tinbase {

// The one place that knows which backends exist. A second backend adds its branch here (a
// "postgresql://" target, say) and nothing above the seam changes.
Result<std::unique_ptr<Connection>> Connection::Open(const std::string& target, Mode mode) {
  TB_ASSIGN_OR_RETURN(auto connection, SqliteConnection::Open(target, mode));
  return std::unique_ptr<Connection>(std::move(connection));
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
