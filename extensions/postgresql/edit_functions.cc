// The edit functions of the PostgreSQL module: tinbase's local update engine run inside the
// server, in the caller's transaction (extensions/postgresql/engine_call.h):
//
//   tinbase_add_polygon_wkb(surface text, wkb bytea, srid integer, mode text, tag text) -> bigint
//   tinbase_remove_feature(surface text, id bigint) -> bigint
//
// functions.sql wraps the first as tinbase_add_polygon(surface, geometry, mode, tag), passing
// ST_AsBinary and ST_SRID of the geometry. Both are `polygon add` and `polygon remove` of the CLI:
// one edit with its `changes` row and feature versions, the features' ids as the CLI gives them.
// Thread-safety: a backend is single-threaded.

#include <ogr_geometry.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/geometry/crs.h"
#include "core/geometry/polygon.h"
#include "core/tin/feature_mode.h"
#include "db/polygon_editor.h"
#include "extensions/postgresql/engine_call.h"

// The server's headers last: their macros (printf, snprintf, ...) would rewrite the standard
// library's; postgres.h must come first among them.
// clang-format off
extern "C" {
#include "postgres.h"
#include "fmgr.h"
#include "utils/builtins.h"
}
// clang-format on

extern "C" {
PG_FUNCTION_INFO_V1(tinbase_add_polygon_wkb);
PG_FUNCTION_INFO_V1(tinbase_remove_feature);
}

namespace tinbase {
namespace {

struct OgrDeleter {
  void operator()(OGRGeometry* g) const { OGRGeometryFactory::destroyGeometry(g); }
};

// One ring of `ring` as read (closed), for MakeValidPolygon.
Ring RingOf(const OGRLinearRing& ring) {
  Ring out;
  out.reserve(static_cast<size_t>(ring.getNumPoints()));
  for (int i = 0; i < ring.getNumPoints(); ++i) out.push_back({ring.getX(i), ring.getY(i)});
  return out;
}

Result<Polygon> ValidPolygon(const OGRPolygon& polygon, const std::string& prefix) {
  std::vector<Ring> rings;
  if (polygon.getExteriorRing() != nullptr) rings.push_back(RingOf(*polygon.getExteriorRing()));
  for (int i = 0; i < polygon.getNumInteriorRings(); ++i)
    rings.push_back(RingOf(*polygon.getInteriorRing(i)));
  auto valid = MakeValidPolygon(rings);
  if (!valid.ok()) return Status::InvalidArgument(prefix + valid.status().message());
  return valid;
}

Result<std::vector<Point2>> LineOf(const OGRLineString& line, const std::string& prefix) {
  std::vector<Point2> out;
  for (int i = 0; i < line.getNumPoints(); ++i) {
    const Point2 p{line.getX(i), line.getY(i)};
    if (!std::isfinite(p.x) || !std::isfinite(p.y))
      return Status::InvalidArgument(prefix + "vertex " + std::to_string(i) +
                                     ": a coordinate is not a finite number");
    if (out.empty() || !SamePoint(out.back(), p)) out.push_back(p);
  }
  if (out.size() < 2)
    return Status::InvalidArgument(prefix + "a line needs at least 2 distinct points");
  return out;
}

// The feature of argument 2: polygons for the area modes, lines for the line modes. Messages
// name the argument, the part and the ring or vertex.
Result<MemoryFeature> FeatureFromWkb(const std::vector<uint8_t>& wkb, FeatureMode mode) {
  OGRGeometry* raw = nullptr;
  if (OGRGeometryFactory::createFromWkb(wkb.data(), nullptr, &raw, wkb.size()) != OGRERR_NONE ||
      raw == nullptr)
    return Status::InvalidArgument("argument 2 (geometry): not a geometry tinbase can read");
  std::unique_ptr<OGRGeometry, OgrDeleter> geometry(raw);
  MemoryFeature feature;
  feature.label = "geometry";
  const OGRwkbGeometryType type = wkbFlatten(geometry->getGeometryType());
  const std::string name = OGRGeometryTypeToName(geometry->getGeometryType());
  if (IsLineMode(mode)) {
    if (type == wkbLineString) {
      TB_ASSIGN_OR_RETURN(auto line, LineOf(*geometry->toLineString(), "argument 2 (geometry), "));
      feature.lines.push_back(std::move(line));
    } else if (type == wkbMultiLineString) {
      const OGRMultiLineString& lines = *geometry->toMultiLineString();
      for (int i = 0; i < lines.getNumGeometries(); ++i) {
        TB_ASSIGN_OR_RETURN(auto line,
                            LineOf(*lines.getGeometryRef(i),
                                   "argument 2 (geometry), line " + std::to_string(i) + ", "));
        feature.lines.push_back(std::move(line));
      }
    } else {
      return Status::InvalidArgument("argument 2 (geometry): mode " +
                                     std::string(FeatureModeName(mode)) +
                                     " takes a LineString or MultiLineString, got " + name);
    }
  } else if (type == wkbPolygon) {
    TB_ASSIGN_OR_RETURN(Polygon p, ValidPolygon(*geometry->toPolygon(), "argument 2 (geometry), "));
    feature.polygons.push_back(std::move(p));
  } else if (type == wkbMultiPolygon) {
    const OGRMultiPolygon& polygons = *geometry->toMultiPolygon();
    for (int i = 0; i < polygons.getNumGeometries(); ++i) {
      TB_ASSIGN_OR_RETURN(
          Polygon p, ValidPolygon(*polygons.getGeometryRef(i),
                                  "argument 2 (geometry), polygon " + std::to_string(i) + ", "));
      feature.polygons.push_back(std::move(p));
    }
  } else {
    return Status::InvalidArgument("argument 2 (geometry): mode " +
                                   std::string(FeatureModeName(mode)) +
                                   " takes a Polygon or MultiPolygon, got " + name);
  }
  if (feature.polygons.empty() && feature.lines.empty())
    return Status::InvalidArgument("argument 2 (geometry): the geometry is empty");
  return feature;
}

// A geometry whose SRID is set must be in the store's CRS: the engine does not reproject.
Status CheckSrid(Store& store, int32_t srid) {
  if (srid == 0) return Status::Ok();
  TB_ASSIGN_OR_RETURN(std::optional<Crs> crs, store.GetCrs());
  const std::optional<int> epsg = crs ? crs->Epsg() : std::nullopt;
  if (epsg && *epsg != srid)
    return Status::InvalidArgument("argument 2 (geometry): SRID " + std::to_string(srid) +
                                   " is not the store's EPSG:" + std::to_string(*epsg) +
                                   " (ST_Transform it first)");
  return Status::Ok();
}

std::string TextOf(text* value) {
  return std::string(VARDATA_ANY(value), VARSIZE_ANY_EXHDR(value));
}

}  // namespace
}  // namespace tinbase

// tinbase_add_polygon_wkb(surface, wkb, srid, mode, tag): the id of the feature added. `tag` may
// be NULL (no tag); the others may not (the SQL wrapper is STRICT in them).
extern "C" Datum tinbase_add_polygon_wkb(PG_FUNCTION_ARGS) {
  using tinbase::EngineError;
  constexpr const char* kFunction = "tinbase_add_polygon";
  if (PG_ARGISNULL(0) || PG_ARGISNULL(1) || PG_ARGISNULL(2) || PG_ARGISNULL(3))
    ereport(ERROR, (errcode(ERRCODE_NULL_VALUE_NOT_ALLOWED),
                    errmsg("tinbase_add_polygon: surface, geometry and mode must not be NULL")));
  text* surface_arg = PG_GETARG_TEXT_PP(0);
  bytea* wkb_arg = PG_GETARG_BYTEA_PP(1);
  const int32 srid = PG_GETARG_INT32(2);
  text* mode_arg = PG_GETARG_TEXT_PP(3);
  text* tag_arg = PG_ARGISNULL(4) ? nullptr : PG_GETARG_TEXT_PP(4);
  const Oid function = fcinfo->flinfo->fn_oid;
  int64_t id = 0;
  EngineError error;
  {
    try {
      const std::string schema = tinbase::FunctionSchema(function);
      tinbase::PolygonAddOptions options;
      options.surface = tinbase::TextOf(surface_arg);
      if (tag_arg != nullptr) options.tag = tinbase::TextOf(tag_arg);
      const std::string mode_text = tinbase::TextOf(mode_arg);
      const auto* bytes = reinterpret_cast<const uint8_t*>(VARDATA_ANY(wkb_arg));
      const std::vector<uint8_t> wkb(bytes, bytes + VARSIZE_ANY_EXHDR(wkb_arg));
      error = tinbase::RunOnStore(kFunction, schema, [&](tinbase::Store& store) -> tinbase::Status {
        auto mode = tinbase::ParseFeatureMode(mode_text);
        if (!mode.ok())
          return tinbase::Status::InvalidArgument("argument 4 (mode): " + mode.status().message());
        options.mode = *mode;
        TB_RETURN_IF_ERROR(tinbase::CheckSrid(store, srid));
        TB_ASSIGN_OR_RETURN(tinbase::MemoryFeature feature, tinbase::FeatureFromWkb(wkb, *mode));
        options.features = std::vector<tinbase::MemoryFeature>{std::move(feature)};
        TB_ASSIGN_OR_RETURN(tinbase::PolygonAddReport report, tinbase::AddPolygons(store, options));
        if (report.feature_ids.empty())
          return tinbase::Status::InvalidArgument("argument 2 (geometry): no feature was added");
        id = report.feature_ids.front();
        return tinbase::Status::Ok();
      });
    } catch (...) {
      error = tinbase::ErrorOf(kFunction, tinbase::Status::IOError("internal error"));
    }
  }
  tinbase::RaiseIfFailed(error);
  PG_RETURN_INT64(id);
}

// tinbase_remove_feature(surface, id): the transaction number of the removal. An error when
// the feature is not one of the surface's.
extern "C" Datum tinbase_remove_feature(PG_FUNCTION_ARGS) {
  using tinbase::EngineError;
  constexpr const char* kFunction = "tinbase_remove_feature";
  text* surface_arg = PG_GETARG_TEXT_PP(0);
  const int64 feature = PG_GETARG_INT64(1);
  const Oid function = fcinfo->flinfo->fn_oid;
  int64_t tx = 0;
  EngineError error;
  {
    try {
      const std::string schema = tinbase::FunctionSchema(function);
      const std::string surface = tinbase::TextOf(surface_arg);
      error = tinbase::RunOnStore(kFunction, schema, [&](tinbase::Store& store) -> tinbase::Status {
        TB_ASSIGN_OR_RETURN(
            tinbase::Statement * owner,
            store.db().Cached("SELECT count(*) FROM features f JOIN surfaces s ON s.id = f.surface "
                              "WHERE f.id = ? AND s.name = ?"));
        owner->Bind(1, static_cast<int64_t>(feature)).Bind(2, surface);
        TB_ASSIGN_OR_RETURN(bool row, owner->Step());
        const int64_t found = row ? owner->ColumnInt(0) : 0;
        owner->Reset();
        if (found == 0)
          return tinbase::Status::NotFound("surface '" + surface + "' has no feature " +
                                           std::to_string(feature));
        TB_ASSIGN_OR_RETURN(tinbase::PolygonAddReport report,
                            tinbase::RemovePolygon(store, feature));
        tx = report.tx;
        return tinbase::Status::Ok();
      });
    } catch (...) {
      error = tinbase::ErrorOf(kFunction, tinbase::Status::IOError("internal error"));
    }
  }
  tinbase::RaiseIfFailed(error);
  PG_RETURN_INT64(tx);
}
