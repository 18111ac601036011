// The set-returning functions of the PostgreSQL module, on the library's own answers:
//
//   tinbase_neighbours(surface text, triangle bigint) -> SETOF bigint: NeighboursOf's triangles
//     across edges 0, 1, 2, the boundary left out;
//   tinbase_check(surface text) -> TABLE(problem text, triangle_id bigint, detail text): every
//     problem `tinbase check --surface S` reports (CheckStore), its code, triangle and words.
//
// Both read in the caller's transaction. The rows are gathered by the engine, copied into the
// call's memory, and handed to PostgreSQL's tuplestore only once no C++ object is alive.
// Thread-safety: a backend is single-threaded.
#include <cstdint>
#include <string>
#include <vector>

#include "db/integrity_check.h"
#include "db/query/topology.h"
#include "db/surface_store.h"
#include "extensions/postgresql/engine_call.h"

// The server's headers last: their macros (printf, snprintf, ...) would rewrite the standard
// library's; postgres.h must come first among them.
// clang-format off
extern "C" {
#include "postgres.h"
#include "fmgr.h"
#include "funcapi.h"
#include "utils/builtins.h"
#include "utils/tuplestore.h"
}
// clang-format on

extern "C" {
PG_FUNCTION_INFO_V1(tinbase_neighbours_c);
PG_FUNCTION_INFO_V1(tinbase_check_c);
}

namespace tinbase {
namespace {

std::string TextOf(text* value) {
  return std::string(VARDATA_ANY(value), VARSIZE_ANY_EXHDR(value));
}

// One row of tinbase_check, in the call's memory.
struct CheckRow {
  char* problem;
  bool has_triangle;
  int64_t triangle;
  char* detail;
};

}  // namespace
}  // namespace tinbase

extern "C" Datum tinbase_neighbours_c(PG_FUNCTION_ARGS) {
  constexpr const char* kFunction = "tinbase_neighbours";
  // A set of a scalar: the row shape is the one the caller expects (one bigint column).
  InitMaterializedSRF(fcinfo, MAT_SRF_USE_EXPECTED_DESC);
  auto* result = reinterpret_cast<ReturnSetInfo*>(fcinfo->resultinfo);
  text* surface_arg = PG_GETARG_TEXT_PP(0);
  const int64 triangle = PG_GETARG_INT64(1);
  const Oid function = fcinfo->flinfo->fn_oid;
  int64 ids[3] = {0, 0, 0};
  int count = 0;
  tinbase::EngineError error;
  try {
    const std::string schema = tinbase::FunctionSchema(function);
    const std::string surface = tinbase::TextOf(surface_arg);
    error = tinbase::RunOnStore(kFunction, schema, [&](tinbase::Store& store) -> tinbase::Status {
      TB_ASSIGN_OR_RETURN(tinbase::SurfaceInfo info, tinbase::SurfaceStore(store).Find(surface));
      TB_ASSIGN_OR_RETURN(tinbase::TriangleNeighbours around,
                          tinbase::NeighboursOf(store, info, triangle));
      for (const tinbase::SharedEdge& edge : around.edges)
        if (edge.neighbour) ids[count++] = *edge.neighbour;
      return tinbase::Status::Ok();
    });
  } catch (...) {
    error = tinbase::ErrorOf(kFunction, tinbase::Status::IOError("internal error"));
  }
  tinbase::RaiseIfFailed(error);
  for (int i = 0; i < count; ++i) {
    Datum value = Int64GetDatum(ids[i]);
    bool null = false;
    tuplestore_putvalues(result->setResult, result->setDesc, &value, &null);
  }
  return static_cast<Datum>(0);
}

extern "C" Datum tinbase_check_c(PG_FUNCTION_ARGS) {
  constexpr const char* kFunction = "tinbase_check";
  InitMaterializedSRF(fcinfo, 0);
  auto* result = reinterpret_cast<ReturnSetInfo*>(fcinfo->resultinfo);
  text* surface_arg = PG_GETARG_TEXT_PP(0);
  const Oid function = fcinfo->flinfo->fn_oid;
  MemoryContext call = CurrentMemoryContext;
  tinbase::CheckRow* rows = nullptr;
  size_t count = 0;
  tinbase::EngineError error;
  try {
    const std::string schema = tinbase::FunctionSchema(function);
    tinbase::CheckOptions options;
    options.surface = tinbase::TextOf(surface_arg);
    std::vector<tinbase::Problem> problems;
    error = tinbase::RunOnStore(kFunction, schema, [&](tinbase::Store& store) -> tinbase::Status {
      TB_ASSIGN_OR_RETURN(problems, tinbase::CheckStore(store, options));
      return tinbase::Status::Ok();
    });
    if (error.ok && !problems.empty()) {
      rows = static_cast<tinbase::CheckRow*>(
          MemoryContextAlloc(call, sizeof(tinbase::CheckRow) * problems.size()));
      for (const tinbase::Problem& p : problems) {
        // The message names the surface and triangle first ("surface 'terrain', triangle 412:
        // vertices are clockwise"); the detail is what follows, as the CLI's JSON gives it.
        const size_t colon = p.message.find(": ");
        const std::string detail =
            colon == std::string::npos ? p.message : p.message.substr(colon + 2);
        rows[count++] = {MemoryContextStrdup(call, p.code.c_str()), p.triangle.has_value(),
                         p.triangle.value_or(0), MemoryContextStrdup(call, detail.c_str())};
      }
    }
  } catch (...) {
    error = tinbase::ErrorOf(kFunction, tinbase::Status::IOError("internal error"));
  }
  tinbase::RaiseIfFailed(error);
  for (size_t i = 0; i < count; ++i) {
    Datum values[3] = {CStringGetTextDatum(rows[i].problem), Int64GetDatum(rows[i].triangle),
                       CStringGetTextDatum(rows[i].detail)};
    bool nulls[3] = {false, !rows[i].has_triangle, false};
    tuplestore_putvalues(result->setResult, result->setDesc, values, nulls);
  }
  return static_cast<Datum>(0);
}
