// GeoJSON request bodies: a Feature or FeatureCollection posted to the edit routes, read into the
// editor's in-memory features (db/polygon_editor.h MemoryFeature).
//
// Everything is checked before the editor sees it, and a bad body is one InvalidArgument naming
// the place, as the CLI names a file's: "features[2], polygon 1, ring 0, vertex 7: ring crosses
// itself at (x, y)". Coordinates are reprojected from the request's CRS to the store's first,
// so the rings are validated where they will be used. properties.mode, properties.tag and
// properties.level set the feature's mode, tag and flat z, properties.z_from ("dem" or "feature")
// whether a line keeps the z of its positions; the other properties become its attributes.
// Survey points (POST /surfaces/{s}/points) are read the same way. Thread-safety: reentrant.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/tin/tin.h"
#include "db/polygon_editor.h"

namespace tinbase::service {

// The features of `body` (a GeoJSON Feature or FeatureCollection, RFC 7946 geometry types
// Polygon, MultiPolygon, LineString, MultiLineString), in `store_crs`. `source_crs`: the CRS of
// the body's coordinates, nullopt when they are already in the store's. InvalidArgument naming
// the place for: malformed JSON (line and column), a body that is not a Feature or collection,
// an empty collection, a feature without geometry or with another type, a position that is not
// 2 or 3 finite numbers, a vertex that cannot be reprojected, an invalid ring or a line of fewer
// than 2 distinct points, a bad properties.mode or properties.z_from, a tag that is not a string,
// a level that is not a number. A line's z (MemoryFeature::line_z) is kept when every one of its
// positions has one; otherwise its entry is empty.
Result<std::vector<MemoryFeature>> ParseGeoJsonFeatures(std::string_view body,
                                                        const std::optional<Crs>& source_crs,
                                                        const Crs& store_crs);

// Survey points read from a request body, in body order, one label each ("features[2], point 0").
struct SurveyPointsBody {
  std::vector<TinVertex> points;
  std::vector<std::string> labels;
};

// The points of `body` (a Feature or FeatureCollection of Point or MultiPoint geometries whose
// every position is x, y, z), in `store_crs`; properties are ignored. InvalidArgument naming the
// place as ParseGeoJsonFeatures, and for another geometry type or a position without z.
Result<SurveyPointsBody> ParseGeoJsonPoints(std::string_view body,
                                            const std::optional<Crs>& source_crs,
                                            const Crs& store_crs);

}  // namespace tinbase::service
