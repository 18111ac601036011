// The point functions of the PostgreSQL module, tinbase_z(surface, x, y) and
// tinbase_locate(surface, x, y): the triangle that holds a point and the surface's z there, by
// the walk of tinbase's bulk location (db/query/memory_locator.h) over the surface held in memory,
// with CGAL's exact orientation tests; NULL outside the surface.
//
// Why in memory: a query such as `SELECT tinbase_z('terrain', x, y) FROM wells` calls the function
// once per row, and a walk over stored rows costs several SPI queries per point. So each
// statement's call site (FmgrInfo.fn_extra) reads the surface once, at its first row, and walks
// in memory for the others, from one answer to the next. Across statements the backend keeps the
// MemoryMesh of the surfaces it was asked about (a few at most), each with the `changes` state it
// was read at (the newest transaction number and the id of the transaction that wrote it, which
// no rollback can give again): a statement's first row checks that state with one query and
// reads the surface again when it moved. Every tinbase writer adds a `changes` row; a hand-written
// UPDATE of the tables by another session adds none and is not seen by a kept mesh. Within a
// transaction that has written anything (its own rows, which a rollback to a savepoint can take
// back without a trace in `changes`) nothing is kept across statements.
// Thread-safety: a backend is single-threaded.

#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "db/query/memory_locator.h"
#include "db/query/memory_mesh.h"
#include "db/surface_store.h"
#include "extensions/postgresql/engine_call.h"

// The server's headers last: their macros (printf, snprintf, ...) would rewrite the standard
// library's; postgres.h must come first among them.
// clang-format off
extern "C" {
#include "postgres.h"
#include "fmgr.h"
#include "utils/builtins.h"
#include "utils/memutils.h"
}
// clang-format on

extern "C" {
PG_FUNCTION_INFO_V1(tinbase_z_c);
PG_FUNCTION_INFO_V1(tinbase_locate_c);
}

namespace tinbase {
namespace {

// One surface held in memory, and the `changes` state it was read at.
struct KeptMesh {
  std::string state;
  SurfaceInfo surface;
  std::optional<MemoryMesh> mesh;
};

// The backend's kept meshes by (schema, surface name). Small: a backend answers few surfaces.
constexpr size_t kMaxKeptMeshes = 4;
std::map<std::pair<std::string, std::string>, std::shared_ptr<KeptMesh>>& KeptMeshes() {
  static auto* kept = new std::map<std::pair<std::string, std::string>, std::shared_ptr<KeptMesh>>;
  return *kept;
}

// What one call site keeps for the rows of its statement.
struct CallSite {
  std::string surface;  // the name it was opened for
  std::shared_ptr<KeptMesh> kept;
  std::unique_ptr<MemoryLocator> locator;
};

void DeleteCallSite(void* site) { delete static_cast<CallSite*>(site); }

// The state of `changes` a kept mesh must match ("-" for a store without edits), or nullopt when
// the calling transaction has written (then nothing may be kept).
Result<std::optional<std::string>> ChangesState(Store& store) {
  TB_ASSIGN_OR_RETURN(
      Statement * q,
      store.db().Cached("SELECT pg_current_xact_id_if_assigned() IS NULL, coalesce((SELECT tx || "
                        "'/' || xmin::text FROM changes ORDER BY tx DESC LIMIT 1), '-')"));
  TB_ASSIGN_OR_RETURN(bool row, q->Step());
  std::optional<std::string> state;
  if (row && q->ColumnInt(0) != 0) state = q->ColumnText(1);
  q->Reset();
  return state;
}

// The kept mesh of `surface` in `schema`, read again when the store changed since.
Result<std::shared_ptr<KeptMesh>> MeshFor(Store& store, const std::string& schema,
                                          const std::string& surface) {
  TB_ASSIGN_OR_RETURN(std::optional<std::string> state, ChangesState(store));
  auto& kept = KeptMeshes();
  const auto key = std::make_pair(schema, surface);
  auto it = kept.find(key);
  if (it != kept.end() && state && it->second->state == *state) return it->second;
  if (it != kept.end()) kept.erase(it);
  auto fresh = std::make_shared<KeptMesh>();
  TB_ASSIGN_OR_RETURN(fresh->surface, SurfaceStore(store).Find(surface));
  TB_ASSIGN_OR_RETURN(fresh->mesh, MemoryMesh::Load(store, fresh->surface));
  if (!fresh->mesh)
    return Status::Corruption("surface '" + surface +
                              "' has links that name no row of it: run tinbase check");
  if (!state) return fresh;
  fresh->state = std::move(*state);
  if (kept.size() >= kMaxKeptMeshes) kept.clear();
  kept[key] = fresh;
  return fresh;
}

enum class Answer { kZ, kTriangle };

// The located point's z or triangle id; nullopt outside the surface.
template <Answer kAnswer>
Datum PointFunction(FunctionCallInfo fcinfo, const char* function) {
  text* surface_arg = PG_GETARG_TEXT_PP(0);
  const double x = PG_GETARG_FLOAT8(1);
  const double y = PG_GETARG_FLOAT8(2);
  if (!std::isfinite(x) || !std::isfinite(y))
    ereport(ERROR, (errcode(ERRCODE_INVALID_PARAMETER_VALUE),
                    errmsg("%s: argument %d (%s) must be a finite number", function,
                           std::isfinite(x) ? 3 : 2, std::isfinite(x) ? "y" : "x")));
  FmgrInfo* flinfo = fcinfo->flinfo;
  const Oid function_oid = flinfo->fn_oid;
  const char* name_data = VARDATA_ANY(surface_arg);
  const size_t name_size = VARSIZE_ANY_EXHDR(surface_arg);
  bool found = false;
  double z = 0;
  int64_t triangle = 0;
  EngineError error;
  {
    try {
      auto* site = static_cast<CallSite*>(flinfo->fn_extra);
      const std::string_view name(name_data, name_size);
      if (site == nullptr || site->surface != name) {
        if (site == nullptr) {
          // Freed with the call site's memory (the statement's end).
          site = new CallSite;
          auto* callback = static_cast<MemoryContextCallback*>(
              MemoryContextAllocZero(flinfo->fn_mcxt, sizeof(MemoryContextCallback)));
          callback->func = DeleteCallSite;
          callback->arg = site;
          MemoryContextRegisterResetCallback(flinfo->fn_mcxt, callback);
          flinfo->fn_extra = site;
        }
        site->locator.reset();
        site->kept.reset();
        site->surface.assign(name);
        const std::string schema = FunctionSchema(function_oid);
        error = RunOnStore(function, schema, [&](Store& store) -> Status {
          TB_ASSIGN_OR_RETURN(site->kept, MeshFor(store, schema, site->surface));
          return Status::Ok();
        });
        if (error.ok) {
          site->locator = std::make_unique<MemoryLocator>(*site->kept->mesh, site->kept->surface);
        } else {
          site->surface.clear();
        }
      }
      if (error.ok) {
        auto where = site->locator->Locate({x, y});
        if (!where.ok()) {
          error = ErrorOf(function, where.status());
        } else if (*where != nullptr) {
          found = true;
          z = (*where)->z;
          triangle = (*where)->triangle;
        }
      }
    } catch (...) {
      error = ErrorOf(function, Status::IOError("internal error"));
    }
  }
  RaiseIfFailed(error);
  if (!found) PG_RETURN_NULL();
  if constexpr (kAnswer == Answer::kZ) {
    PG_RETURN_FLOAT8(z);
  } else {
    PG_RETURN_INT64(triangle);
  }
}

}  // namespace
}  // namespace tinbase

extern "C" Datum tinbase_z_c(PG_FUNCTION_ARGS) {
  return tinbase::PointFunction<tinbase::Answer::kZ>(fcinfo, "tinbase_z");
}

extern "C" Datum tinbase_locate_c(PG_FUNCTION_ARGS) {
  return tinbase::PointFunction<tinbase::Answer::kTriangle>(fcinfo, "tinbase_locate");
}
