// Polygon and line sources: features read from any vector file OGR opens (GeoJSON,
// GeoPackage, shapefile, KML, ...), validated and reprojected, ready to become clip / erase /
// fill / replace polygons or breaklines of a surface.
//
// Everything is read into memory and checked before anything is returned, so a caller either
// gets every feature or one error naming the file, feature (its OGR FID, as ogrinfo shows it),
// polygon part, ring and vertex: "lux.shp feature 3, ring 0, vertex 7: ring crosses itself at
// (x, y) (edges 7-8 and 12-13)". Coordinates are 2D; z is dropped because features are draped
// on the DEM. Thread-safety: functions are reentrant (each opens its own dataset).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/geometry/polygon.h"

namespace tinbase {

struct VectorSourceOptions {
  std::string layer;      // layer name; empty: the source's only layer
  std::string where;      // OGR attribute filter (SQL WHERE clause); empty: every feature
  std::string tag_field;  // field whose value becomes the feature's tag; empty: no tag
  // Coordinates are returned in this CRS; nullopt: as stored in the source.
  std::optional<Crs> target_crs;
  // The source's CRS when it declares none (a shapefile without .prj); ignored otherwise.
  std::optional<Crs> assumed_source_crs;
  // Polygons only: run GEOS's MakeValid (through OGR) on each geometry first, keeping the
  // polygonal parts of its result, so self-intersecting rings become valid polygons instead of
  // errors.
  bool repair = false;
  // When set, a feature whose geometry is invalid (InvalidArgument) is listed here as
  // "label: message" and skipped, and the read goes on (`polygon add --each`); unset, the first
  // invalid feature fails the read. Errors of the source itself fail it either way.
  std::vector<std::string>* rejected = nullptr;
};

struct PolygonFeature {
  int64_t fid = 0;                                       // OGR feature id
  std::string label;                                     // "lux.shp feature 3", for messages
  std::vector<Polygon> polygons;                         // one per part of a MultiPolygon
  nlohmann::json attributes = nlohmann::json::object();  // field name -> value (null if unset)
  std::optional<std::string> tag;                        // tag_field's value, unless null
};

struct LineFeature {
  int64_t fid = 0;
  std::string label;
  std::vector<std::vector<Point2>> lines;  // one per part of a MultiLineString
  nlohmann::json attributes = nlohmann::json::object();
  std::optional<std::string> tag;
  // The source's z of each kept vertex (z[k][i] for lines[k][i]; NaN where the geometry has no
  // z), for lines that keep their own z; has_z: every part has z. z is not reprojected.
  std::vector<std::vector<double>> z;
  bool has_z = false;
};

// The polygon features of `path` (Polygon or MultiPolygon geometries), each polygon valid
// (MakeValidPolygon) in the target CRS. Errors: NotFound when the file does not exist;
// InvalidArgument naming the file for: unreadable data, an unknown or ambiguous layer, an
// unknown tag field, a bad filter, no features, a feature without geometry or with a
// non-polygon one, an invalid ring (MakeValidPolygon's message after the feature's label), a
// source without CRS when a target CRS is asked for, a vertex that cannot be reprojected.
Result<std::vector<PolygonFeature>> ReadPolygonFeatures(const std::string& path,
                                                        const VectorSourceOptions& options);

// The line features of `path` (LineString or MultiLineString), e.g. faults used as breaklines:
// consecutive repeated points are dropped; each line must keep at least 2 distinct points, all
// finite. Errors as for ReadPolygonFeatures, with "line k, vertex v" in place of rings.
Result<std::vector<LineFeature>> ReadLineFeatures(const std::string& path,
                                                  const VectorSourceOptions& options);

// The CRS the source's layer declares, nullopt when it declares none (options.target_crs and
// assumed_source_crs are ignored). Errors as ReadPolygonFeatures for the file and the layer.
Result<std::optional<Crs>> ReadVectorCrs(const std::string& path,
                                         const VectorSourceOptions& options);

}  // namespace tinbase
