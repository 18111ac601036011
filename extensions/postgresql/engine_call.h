// EngineCall: how an entry point of the PostgreSQL module runs tinbase's C++ engine on its store,
// with neither a C++ exception nor a PostgreSQL error (a longjmp) crossing the other's frames.
//
// The entry point (a PG_FUNCTION_INFO_V1 function, plain C in spirit) reads its arguments, calls
// RunOnStore, and, once every C++ object of the call is gone, raises the returned error with
// RaiseIfFailed. RunOnStore connects SPI, opens an SpiConnection on the store in the function's
// own schema (the schema CREATE EXTENSION put it in), adopts it as a Store and runs `body`; it
// catches every C++ exception, and SpiConnection catches every server error. Whatever the body
// wrote stays in the caller's transaction on success and is rolled back on failure.
// Thread-safety: a backend is single-threaded.
#pragma once

#include <functional>
#include <string>

#include "core/base/status.h"
#include "db/store.h"

namespace tinbase {

// A failed call: its SQLSTATE (a MAKE_SQLSTATE value) and message, palloc'd in the memory context
// that was current when RunOnStore was called. ok == true: nothing to raise.
struct EngineError {
  bool ok = true;
  int sqlstate = 0;
  char* message = nullptr;
};

// The schema of the function being called (fn_oid of its FmgrInfo): the store's schema. Raises a
// PostgreSQL error when the catalogue has no such function (call from the entry point's C part).
std::string FunctionSchema(unsigned function_oid);

// Runs `body` on the store in `schema`, as described above. `function` prefixes the message.
EngineError RunOnStore(const char* function, const std::string& schema,
                       const std::function<Status(Store&)>& body) noexcept;

// The EngineError of a Status or a message (for the entry points' own argument checks), or of
// a C++ exception that escaped a body run outside RunOnStore.
EngineError ErrorOf(const char* function, const Status& status) noexcept;

// ereport(ERROR) when !error.ok. REQUIRES: no C++ object with a destructor alive in the caller.
void RaiseIfFailed(const EngineError& error);

}  // namespace tinbase
