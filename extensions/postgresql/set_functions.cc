// The set-returning functions of the PostgreSQL module, on the library's own answers:
//
//   tinbase_neighbours(surface text, triangle bigint) -> SETOF bigint: NeighboursOf's triangles
//     across edges 0, 1, 2, the boundary left out;
//   tinbase_check(surface text) -> TABLE(problem text, triangle_id bigint, detail text): every
//     problem `tinbase check --surface S` reports (CheckStore), its code, triangle and words;
//   tinbase_profile_wkb(surface text, line bytea) -> TABLE(distance, x, y, z, kind, triangle,
//     visible, tag): `tinbase profile`'s stations (ProfileAlong) along a WKB LineString, each with
//     the stretch that begins there (none at the end). functions.sql wraps it as
//     tinbase_profile(surface, geometry).
//
// Both read in the caller's transaction. The rows are gathered by the engine, copied into the
// call's memory, and handed to PostgreSQL's tuplestore only once no C++ object is alive.
// Thread-safety: a backend is single-threaded.
#include <ogr_geometry.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/query/line_walk.h"
#include "db/integrity_check.h"
#include "db/query/profile.h"
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
PG_FUNCTION_INFO_V1(tinbase_profile_wkb);
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

// One row of tinbase_profile.
struct ProfileRow {
  double distance, x, y, z;
  const char* kind;  // a static name
  bool has_stretch;
  int64_t triangle;
  bool visible;
  char* tag;  // null: no tag
};

// The points of a WKB LineString (argument 2).
Result<std::vector<Point2>> LineFromWkb(const uint8_t* data, size_t size) {
  OGRGeometry* raw = nullptr;
  if (OGRGeometryFactory::createFromWkb(data, nullptr, &raw, size) != OGRERR_NONE || raw == nullptr)
    return Status::InvalidArgument("argument 2 (line): not a geometry tinbase can read");
  std::unique_ptr<OGRGeometry, void (*)(OGRGeometry*)> geometry(
      raw, [](OGRGeometry* g) { OGRGeometryFactory::destroyGeometry(g); });
  if (wkbFlatten(geometry->getGeometryType()) != wkbLineString)
    return Status::InvalidArgument(std::string("argument 2 (line): a LineString, got ") +
                                   OGRGeometryTypeToName(geometry->getGeometryType()));
  const OGRLineString& line = *geometry->toLineString();
  std::vector<Point2> points;
  for (int i = 0; i < line.getNumPoints(); ++i) points.push_back({line.getX(i), line.getY(i)});
  return points;
}

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

extern "C" Datum tinbase_profile_wkb(PG_FUNCTION_ARGS) {
  constexpr const char* kFunction = "tinbase_profile";
  InitMaterializedSRF(fcinfo, 0);
  auto* result = reinterpret_cast<ReturnSetInfo*>(fcinfo->resultinfo);
  text* surface_arg = PG_GETARG_TEXT_PP(0);
  bytea* wkb_arg = PG_GETARG_BYTEA_PP(1);
  const Oid function = fcinfo->flinfo->fn_oid;
  MemoryContext call = CurrentMemoryContext;
  tinbase::ProfileRow* rows = nullptr;
  size_t count = 0;
  tinbase::EngineError error;
  try {
    const std::string schema = tinbase::FunctionSchema(function);
    const std::string surface = tinbase::TextOf(surface_arg);
    const auto* bytes = reinterpret_cast<const uint8_t*>(VARDATA_ANY(wkb_arg));
    const size_t size = VARSIZE_ANY_EXHDR(wkb_arg);
    tinbase::SurfaceProfile profile;
    error = tinbase::RunOnStore(kFunction, schema, [&](tinbase::Store& store) -> tinbase::Status {
      TB_ASSIGN_OR_RETURN(std::vector<tinbase::Point2> line, tinbase::LineFromWkb(bytes, size));
      TB_ASSIGN_OR_RETURN(tinbase::SurfaceInfo info, tinbase::SurfaceStore(store).Find(surface));
      TB_ASSIGN_OR_RETURN(profile, tinbase::ProfileAlong(store, info, line));
      return tinbase::Status::Ok();
    });
    if (error.ok && !profile.stations.empty()) {
      rows = static_cast<tinbase::ProfileRow*>(
          MemoryContextAlloc(call, sizeof(tinbase::ProfileRow) * profile.stations.size()));
      for (size_t i = 0; i < profile.stations.size(); ++i) {
        const tinbase::Station& s = profile.stations[i];
        tinbase::ProfileRow row{s.distance, s.x, s.y,   s.z,    tinbase::StationKindName(s.kind),
                                false,      0,   false, nullptr};
        if (i < profile.stretches.size()) {
          const tinbase::ProfileStretch& stretch = profile.stretches[i];
          row.has_stretch = true;
          row.triangle = stretch.triangle;
          row.visible = stretch.visible;
          if (stretch.tag) row.tag = MemoryContextStrdup(call, stretch.tag->c_str());
        }
        rows[count++] = row;
      }
    }
  } catch (...) {
    error = tinbase::ErrorOf(kFunction, tinbase::Status::IOError("internal error"));
  }
  tinbase::RaiseIfFailed(error);
  for (size_t i = 0; i < count; ++i) {
    const tinbase::ProfileRow& r = rows[i];
    Datum values[8] = {Float8GetDatum(r.distance),
                       Float8GetDatum(r.x),
                       Float8GetDatum(r.y),
                       Float8GetDatum(r.z),
                       CStringGetTextDatum(r.kind),
                       Int64GetDatum(r.triangle),
                       BoolGetDatum(r.visible),
                       r.tag != nullptr ? CStringGetTextDatum(r.tag) : static_cast<Datum>(0)};
    bool nulls[8] = {false, false,          false,          false,
                     false, !r.has_stretch, !r.has_stretch, r.tag == nullptr};
    tuplestore_putvalues(result->setResult, result->setDesc, values, nulls);
  }
  return static_cast<Datum>(0);
}
