// PgRowStream: the PostgreSQL backend's row stream (db/sql/connection.h, RowStream), rows sent
// with `COPY table(columns) FROM STDIN` in COPY's text format instead of multi-row INSERTs.
//
// Why: a multi-row INSERT makes the server parse its parameters one by one and libpq send them as
// separate values; COPY's rows are one tab-separated line each, sent in large chunks, and the
// server reads them with no statement per batch. The rows go through the table's triggers and
// constraints as inserted ones do (the id triggers of the schema number them in order, as COPY
// inserts one row at a time into a table with BEFORE ROW triggers).
// Errors of a row surface at Finish(): the server reports them when the stream ends.
// Thread-safety: as its connection, which runs nothing else until the stream is finished or
// destroyed.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/status.h"
#include "db/sql/connection.h"

struct pg_conn;

namespace tinbase {

// `value` as a field of COPY's text format: backslash, tab, newline and carriage return escaped.
void AppendCopyText(std::string_view value, std::string* out);

// `bytes` as a bytea field of COPY's text format: "\\x" and two hex digits a byte.
void AppendCopyBytea(const void* bytes, size_t size, std::string* out);

class PgRowStream final : public RowStream {
 public:
  // Starts the COPY on `conn` (inside its open transaction); the mapped error when the server
  // refuses it (no such table or column).
  static Result<std::unique_ptr<PgRowStream>> Begin(pg_conn* conn,
                                                    std::string_view table_and_columns,
                                                    int columns);
  // Abandons the COPY when unfinished (the server then fails the transaction).
  ~PgRowStream() override;

  PgRowStream& Bind(int index, int64_t value) override;
  PgRowStream& Bind(int index, double value) override;
  PgRowStream& Bind(int index, std::string_view text) override;
  PgRowStream& BindStaticText(int index, const char* text) override;
  PgRowStream& BindBlob(int index, const void* data, size_t size) override;
  PgRowStream& BindNull(int index) override;

  // Each ends the row bound so far (Step returns false: a stream has no rows to read).
  Result<bool> Step() override;
  Status Run() override;
  Status Finish() override;

 private:
  PgRowStream(pg_conn* conn, std::string sql, int columns);
  std::string& At(int index);
  // Sends the ended rows; on failure ends the stream (End).
  Status Send();
  // Ends the COPY (dropping its rows when `sent` is an error) and gives the server's error if it
  // reported one, else `sent`.
  Status End(Status sent);

  pg_conn* conn_;
  std::vector<std::string> fields_;  // the row being bound, each field in COPY's text form
  std::string buffer_;               // ended rows not yet sent
  bool open_ = true;
};

}  // namespace tinbase
