// Bulk row writes: many rows of one table inserted through multi-row statements, with their ids
// left out or left to SQLite in a known sequence, and one statement run over many ids at once (an
// IN list).
//
// Used by every writer of many rows at once (SurfaceStore's surface writes, the update engine's
// patches). The functions run statements on the caller's connection inside the caller's
// WriteTransaction; an error leaves the rollback to it. Built on the Connection interface only;
// a backend supplies the head of its insert (Connection::BulkInsertHead) and either numbers rows
// inserted without an id as 1 + the largest id (InsertNumberedRows checks that it did) or says it
// does not (Connection::NumbersRowsByLargestId), and then each row is given its reserved id.
// Thread-safety: as the connection.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "core/base/status.h"
#include "db/sql/connection.h"

namespace tinbase {

// The first of `count` fresh consecutive ids of `table` (Connection::ReserveIds: 1 + the largest
// id on a single-writer store), so a batch of rows can be given ids before it is written.
inline Result<int64_t> NextId(Connection& db, const char* table, size_t count) {
  return db.ReserveIds(table, static_cast<int64_t>(std::max<size_t>(count, 1)));
}

namespace bulk_internal {

// The statement `text(size)` for size = kBatchRows, then halving sizes down to 1, each run as
// often as it fits into what is left of `count`: `run(stmt, first, size)` binds and runs one
// batch of items first .. first + size - 1. One statement step, reset and program start per batch
// instead of per item takes most of the per-row overhead out of a bulk write (docs/BENCHMARKS.md
// has the figures); the halving batches give that to the update engine's patches too, which are
// mostly under 64 rows. The texts are built once per thread and `key`.
template <typename Text, typename Run>
Status InBatches(Connection& db, const std::string& key, size_t count, Text text, Run run) {
  static constexpr size_t kBatchRows = 64;  // 10 columns: 640 parameters, far below SQLite's cap
  thread_local std::unordered_map<std::string, std::string> texts;
  size_t done = 0;
  for (size_t size = kBatchRows; size > 0 && done < count; size /= 2) {
    if (count - done < size) continue;
    std::string& sql = texts[key + "/" + std::to_string(size)];
    if (sql.empty()) sql = text(size);
    TB_ASSIGN_OR_RETURN(Statement * batch, db.Cached(sql));
    for (; done + size <= count; done += size) TB_RETURN_IF_ERROR(run(*batch, done, size));
  }
  return Status::Ok();
}

// Rows of `columns` parameters for a VALUES list: "(?, ?), (?, ?)" for 2 columns and 2 rows.
inline std::string ParameterRows(int columns, size_t rows) {
  std::string row = "(?";
  for (int c = 1; c < columns; ++c) row += ", ?";
  row += ")";
  std::string text = row;
  for (size_t r = 1; r < rows; ++r) text += ", " + row;
  return text;
}

// The backend's row stream (Connection::BeginRowStream) for a write of `rows` rows when it has one
// and the write is large; null otherwise. A stream's start and end cost a round trip or two, more
// than one small batch.
inline Result<std::unique_ptr<RowStream>> StreamFor(Connection& db, std::string_view table,
                                                    int columns, size_t rows) {
  static constexpr size_t kStreamRows = 512;
  if (rows < kStreamRows) return std::unique_ptr<RowStream>();
  return db.BeginRowStream(table, columns);
}

// Streams `rows` rows, `bind(stream, r)` binding row r's values, then ends the stream.
template <typename Bind>
Status StreamRows(RowStream& stream, size_t rows, Bind bind) {
  for (size_t r = 0; r < rows; ++r) {
    bind(stream, r);
    TB_RETURN_IF_ERROR(stream.Run());
  }
  return stream.Finish();
}

}  // namespace bulk_internal

// Writes `rows` rows into `table_and_columns` ("table(a, b)") in batches (InBatches above).
// `bind_row(stmt, first, r)` binds row r's values to parameters first, first + 1, ... in the
// order of `columns`.
//
// Many rows go through the backend's row stream when it has one (COPY on PostgreSQL). Otherwise
// the statements begin with the connection's BulkInsertHead(), in SQLite INSERT OR FAIL: a row that
// breaks a constraint stops the statement with the error but leaves its earlier rows, which is no
// different here, as every caller returns the error and its WriteTransaction rolls the whole write
// back. What it saves: with the default ABORT a multi-row statement must be undoable by itself,
// so SQLite copies every page it is about to change into a statement journal first (foreign keys
// to check still need one; it stays in memory, db/sqlite/sqlite_connection.cc).
template <typename BindRow>
Status InsertRows(Connection& db, const char* table_and_columns, int columns, size_t rows,
                  BindRow bind_row) {
  TB_ASSIGN_OR_RETURN(std::unique_ptr<RowStream> stream,
                      bulk_internal::StreamFor(db, table_and_columns, columns, rows));
  if (stream != nullptr)
    return bulk_internal::StreamRows(*stream, rows,
                                     [&](Statement& row, size_t r) { bind_row(row, 1, r); });
  const std::string head = std::string(db.BulkInsertHead()) + table_and_columns + " VALUES ";
  return bulk_internal::InBatches(
      db, head, rows,
      [&](size_t size) { return head + bulk_internal::ParameterRows(columns, size); },
      [&](Statement& batch, size_t first, size_t size) {
        for (size_t k = 0; k < size; ++k)
          bind_row(batch, static_cast<int>(k) * columns + 1, first + k);
        return batch.Run();
      });
}

// Runs `statement_head` + "(?k, ?k+1, ...)" + `statement_tail` over `ids` in batches, the ids
// bound after `fixed` leading parameters that `bind_fixed(stmt)` binds ("UPDATE t SET a = ?1
// WHERE id IN", "": fixed 1). Adds the rows each statement changed to *changes when given. Pays
// where one statement per id costs much more than a row (an UPDATE of a foreign key column runs
// in two passes); SQLite builds a temporary table of the list for each statement, which made a
// DELETE of a few rows dearer than one statement per id.
template <typename BindFixed>
Status RunOverIds(Connection& db, const std::string& statement_head,
                  const std::string& statement_tail, int fixed, const std::vector<int64_t>& ids,
                  BindFixed bind_fixed, int64_t* changes = nullptr) {
  return bulk_internal::InBatches(
      db, statement_head + "#" + statement_tail, ids.size(),
      [&](size_t size) {
        std::string text = statement_head + " (?" + std::to_string(fixed + 1);
        for (size_t k = 1; k < size; ++k) text += ", ?" + std::to_string(fixed + 1 + k);
        return text + ")" + statement_tail;
      },
      [&](Statement& batch, size_t first, size_t size) -> Status {
        bind_fixed(batch);
        for (size_t k = 0; k < size; ++k)
          batch.Bind(fixed + 1 + static_cast<int>(k), ids[first + k]);
        TB_RETURN_IF_ERROR(batch.Run());
        if (changes != nullptr) *changes += db.Changes();
        return Status::Ok();
      });
}

// As InsertRows, for rows whose ids are to be first_id, first_id + 1, ... in row order, where
// first_id is 1 + the largest id in the table (NextId): `table_and_columns` leaves the id out and
// SQLite numbers each row 1 + the largest rowid before it, as it does for an INTEGER PRIMARY KEY
// without AUTOINCREMENT (sqlite.org/autoinc.html; the PostgreSQL schema gives its id columns a
// trigger that does the same). That is the same number, without the uniqueness seek SQLite makes
// for an id that is given and without its parameter, a good part of a bulk row's cost. Corruption,
// after the rows are written, when the last row did not get the id it was meant to (another row was
// inserted between NextId and these); the caller's transaction then rolls back.
//
// On a backend that does not number rows so (NumbersRowsByLargestId false: concurrent writers
// draw ids from a sequence), first_id comes from NextId's reservation and each row is written with
// its id, as the first column.
template <typename BindRow>
Status InsertNumberedRows(Connection& db, const char* table_and_columns, int columns, size_t rows,
                          int64_t first_id, BindRow bind_row) {
  if (!db.NumbersRowsByLargestId()) {
    std::string with_id(table_and_columns);
    with_id.insert(with_id.find('(') + 1, "id, ");
    return InsertRows(db, with_id.c_str(), columns + 1, rows, [&](Statement& row, int p, size_t r) {
      row.Bind(p, first_id + static_cast<int64_t>(r));
      bind_row(row, p + 1, r);
    });
  }
  TB_RETURN_IF_ERROR(InsertRows(db, table_and_columns, columns, rows, bind_row));
  const std::string table(table_and_columns, std::strcspn(table_and_columns, "("));
  if (rows == 0) return Status::Ok();
  const int64_t last = first_id + static_cast<int64_t>(rows) - 1;
  TB_ASSIGN_OR_RETURN(int64_t largest, db.QueryInt("SELECT max(id) FROM " + table));
  if (largest != last)
    return Status::Corruption(std::string(table_and_columns) + ": rows numbered up to " +
                              std::to_string(largest) + " instead of " + std::to_string(last));
  return Status::Ok();
}

}  // namespace tinbase
