// PolygonEditor: inserts polygon and line features into a surface in one transaction
// (DESIGN.md, "Inserting a polygon").
//
// Walking-skeleton form: the features are read and validated (core/vector/polygon_source),
// their rings draped on the surface's DEM and densified to the surface tolerance, and the whole
// surface is re-triangulated with every constraint (core/tin/constrained_rebuild); visibility and
// tags are then recomputed from all of the surface's features (core/tin/feature_paint) and the
// DEM's data mask, and the surface rows replaced. Re-triangulating only the conflict region is
// issue 5's update engine. Any error leaves the store as it was. Thread-safety: one Store.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "db/store.h"

namespace tinbase {

struct PolygonAddOptions {
  std::string surface;
  std::string file;
  std::string layer;      // OGR layer; empty: the only one
  std::string where;      // OGR attribute filter
  std::string mode;       // clip, erase, fill, replace, breakline
  std::string tag_field;  // the field whose value tags the triangles (fill, replace)
  std::string tag;        // or one tag for every feature
  std::optional<double> level;  // replace: the flat z
};

struct PolygonAddReport {
  int64_t features = 0;
  int64_t ring_vertices = 0;  // after draping and densifying
  int64_t removed = 0;        // triangles
  int64_t added = 0;
  int64_t visible = 0;
  int64_t first_feature_id = 0;
  int64_t tx = 0;
};

// InvalidArgument naming the file, feature, ring and vertex for bad input; NotFound for an
// unknown surface; the store is unchanged on every error.
Result<PolygonAddReport> AddPolygons(Store& store, const PolygonAddOptions& options);

}  // namespace tinbase
