#include "extensions/postgresql/engine_call.h"

#include <exception>
#include <memory>
#include <new>
#include <utility>

#include "extensions/postgresql/spi_connection.h"

// The server's headers last: their macros (printf, snprintf, ...) would rewrite the standard
// library's; postgres.h must come first among them.
// clang-format off
extern "C" {
#include "postgres.h"
#include "executor/spi.h"
#include "utils/builtins.h"
#include "utils/elog.h"
#include "utils/lsyscache.h"
#include "utils/memutils.h"
}
// clang-format on

namespace tinbase {
namespace {

int SqlState(StatusCode code) {
  switch (code) {
    // An unknown surface or feature is a bad argument, as the SQL functions say it.
    case StatusCode::kNotFound:
    case StatusCode::kInvalidArgument:
      return ERRCODE_INVALID_PARAMETER_VALUE;
    case StatusCode::kCorruption:
      return ERRCODE_DATA_CORRUPTED;
    case StatusCode::kConflict:
      return ERRCODE_INTEGRITY_CONSTRAINT_VIOLATION;
    case StatusCode::kBusy:
      return ERRCODE_LOCK_NOT_AVAILABLE;
    default:
      return ERRCODE_SYSTEM_ERROR;
  }
}

// `text` copied into `context`; null when even that fails (the raise then says so).
char* CopyInto(MemoryContext context, const std::string& text) noexcept {
  char* volatile out = nullptr;
  PG_TRY();
  { out = MemoryContextStrdup(context, text.c_str()); }
  PG_CATCH();
  { FlushErrorState(); }
  PG_END_TRY();
  return out;
}

// The store's search_path: the one CREATE EXTENSION ran with, which tinbase_search_path()
// (functions.sql, SET search_path FROM CURRENT) gives back, so PostGIS is found wherever it is.
Status PinSearchPath(SpiConnection& db) {
  TB_ASSIGN_OR_RETURN(Statement * path, db.Cached("SELECT tinbase_search_path()"));
  TB_ASSIGN_OR_RETURN(bool row, path->Step());
  if (!row) return Status::Corruption("tinbase_search_path() gave no row");
  const std::string value = path->ColumnText(0);
  path->Reset();
  return db.SetSearchPath(value);
}

}  // namespace

std::string FunctionSchema(unsigned function_oid) {
  const Oid schema = get_func_namespace(function_oid);
  const char* name = get_namespace_name(schema);
  if (name == nullptr) elog(ERROR, "tinbase: function %u has no schema", function_oid);
  return name;
}

EngineError ErrorOf(const char* function, const Status& status) noexcept {
  EngineError error;
  if (status.ok()) return error;
  error.ok = false;
  error.sqlstate = SqlState(status.code());
  try {
    error.message = CopyInto(CurrentMemoryContext, std::string(function) + ": " + status.message());
  } catch (...) {
    error.message = nullptr;
  }
  return error;
}

EngineError RunOnStore(const char* function, const std::string& schema,
                       const std::function<Status(Store&)>& body) noexcept {
  MemoryContext caller = CurrentMemoryContext;
  if (SPI_connect() != SPI_OK_CONNECT)
    return ErrorOf(function, Status::IOError("cannot connect to SPI"));
  Status status;
  try {
    std::string quoted = "\"";
    for (char c : schema) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    quoted += '"';
    auto db = SpiConnection::Open(schema, quoted);
    if (!db.ok()) {
      status = db.status();
    } else {
      SpiConnection* raw = db->get();
      status = PinSearchPath(*raw);
      std::unique_ptr<Store> store;
      if (status.ok()) {
        // Adopt owns the connection from here; when it refuses, the connection is gone and has
        // rolled its subtransaction back.
        auto adopted = Store::Adopt(std::move(*db));
        if (adopted.ok()) {
          store = std::move(*adopted);
        } else {
          status = adopted.status();
        }
      }
      if (store != nullptr) {
        if (status.ok()) status = body(*store);
        Status finished = raw->Finish(status.ok());
        if (status.ok()) status = finished;
      }
    }
  } catch (const std::bad_alloc&) {
    status = Status::IOError("out of memory");
  } catch (const std::exception& e) {
    status = Status::IOError(std::string("internal error: ") + e.what());
  } catch (...) {
    status = Status::IOError("internal error");
  }
  // SPI_finish frees SPI's memory: the message goes to the caller's context.
  MemoryContextSwitchTo(caller);
  SPI_finish();
  MemoryContextSwitchTo(caller);
  return ErrorOf(function, status);
}

void RaiseIfFailed(const EngineError& error) {
  if (error.ok) return;
  ereport(ERROR,
          (errcode(error.sqlstate),
           errmsg("%s", error.message != nullptr ? error.message : "tinbase: out of memory")));
}

}  // namespace tinbase
