// Bulk row inserts: many rows of one table written through multi-row INSERT statements, with
// their ids either left out or left to SQLite in a known sequence.
//
// Used by every writer of many rows at once (SurfaceStore's surface writes, the update engine's
// patches). The functions run statements on the caller's connection inside the caller's
// WriteTransaction; an error leaves the rollback to it. Thread-safety: as the connection.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>

#include "core/base/status.h"
#include "db/sqlite/sqlite_db.h"

namespace tinbase {

// 1 + the largest id in `table`, so a batch of rows can be given ids before it is written.
inline Result<int64_t> NextId(SqliteDb& db, const char* table) {
  TB_ASSIGN_OR_RETURN(int64_t max_id,
                      db.QueryInt(std::string("SELECT coalesce(max(id), 0) FROM ") + table));
  return max_id + 1;
}

// Writes `rows` rows through multi-row INSERTs of kBatchRows rows each, then the rest in batches
// of halving size (32, 16, ... 1 rows: one statement per bit of the remainder).
// `bind_row(stmt, first, r)` binds row r's values to parameters first, first + 1, ... in the
// order of `columns`. One statement step, reset and program start per batch instead of per row
// halves SQLite's cost per row of a bulk write (about 1.6 to 0.8 us a triangle row); the halving
// batches give that to the update engine's patches too, which are mostly under 64 rows.
//
// The statements are INSERT OR FAIL: a row that breaks a constraint stops the statement with
// the error but leaves its earlier rows, which is no different here, as every caller returns
// the error and its WriteTransaction rolls the whole write back. What it saves: with the default
// ABORT a multi-row statement must be undoable by itself, so SQLite copies every page it is about
// to change into a statement journal first; once one statement has needed more than 64 KiB that
// journal is a temporary file for the rest of the transaction, and a bulk import wrote ~2.7
// pages (8 KiB in two pwrites each) to it per 64-row statement: 260 000 system calls at 1 M
// points, most of the writing thread's kernel time.
template <typename BindRow>
Status InsertRows(SqliteDb& db, const char* table_and_columns, int columns, size_t rows,
                  BindRow bind_row) {
  static constexpr size_t kBatchRows = 64;  // 10 columns: 640 parameters, far below SQLite's cap
  // The statements' text, built once per thread: a small patch asks for several batch sizes.
  thread_local std::unordered_map<std::string, std::string> texts;
  const auto sql = [&](size_t batch) -> const std::string& {
    std::string& text = texts[std::string(table_and_columns) + "/" + std::to_string(batch)];
    if (!text.empty()) return text;
    std::string row = "(?";
    for (int c = 1; c < columns; ++c) row += ", ?";
    row += ")";
    text = std::string("INSERT OR FAIL INTO ") + table_and_columns + " VALUES " + row;
    for (size_t r = 1; r < batch; ++r) text += ", " + row;
    return text;
  };
  size_t r = 0;
  for (size_t size = kBatchRows; size > 0 && r < rows; size /= 2) {
    if (rows - r < size) continue;
    TB_ASSIGN_OR_RETURN(Statement * batch, db.Cached(sql(size)));
    for (; r + size <= rows; r += size) {
      for (size_t k = 0; k < size; ++k) bind_row(*batch, static_cast<int>(k) * columns + 1, r + k);
      TB_RETURN_IF_ERROR(batch->Run());
    }
  }
  return Status::Ok();
}

// As InsertRows, for rows whose ids are to be first_id, first_id + 1, ... in row order, where
// first_id is 1 + the largest id in the table (NextId): `table_and_columns` leaves the id out and
// SQLite numbers each row 1 + the largest rowid before it, as it does for an INTEGER PRIMARY KEY
// without AUTOINCREMENT (sqlite.org/autoinc.html). That is the same number, without the
// uniqueness seek SQLite makes for an id that is given and without its parameter: about a quarter
// of a bulk row's cost (0.67 to 0.51 us a triangle row, 0.63 to 0.48 a vertex row, in a bare
// loop). Corruption, after the rows are written, when the last row did not get the id it was
// meant to (another row was inserted between NextId and these); the caller's transaction then
// rolls back.
template <typename BindRow>
Status InsertNumberedRows(SqliteDb& db, const char* table_and_columns, int columns, size_t rows,
                          int64_t first_id, BindRow bind_row) {
  TB_RETURN_IF_ERROR(InsertRows(db, table_and_columns, columns, rows, bind_row));
  const int64_t last = first_id + static_cast<int64_t>(rows) - 1;
  if (rows > 0 && db.LastInsertRowId() != last)
    return Status::Corruption(std::string(table_and_columns) + ": rows numbered up to " +
                              std::to_string(db.LastInsertRowId()) + " instead of " +
                              std::to_string(last));
  return Status::Ok();
}

}  // namespace tinbase
