// Measure sources: what the measures of core/measure/ read from a store — the visible part of a
// surface as a SurfaceFilter selects it, the metric frame of the store's CRS, and polygons to
// measure inside (a stored feature's, or a vector file's in the store's CRS).
// Thread-safety: as the Store it reads.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/geometry/polygon.h"
#include "core/measure/metric_frame.h"
#include "db/query/surface_selection.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

struct MeasureSource {
  SurfaceInfo surface;
  LoadedSurface part;  // the selection, visible triangles only
  std::optional<Crs> crs;
  MetricFrame frame = MetricFrame::Projected();
};

// Surface `name`'s visible triangles within `filter` (its visible_only is forced on), with the
// store's CRS and frame. Errors: NotFound for an unknown surface or an empty selection
// (SelectSurface's message), MetricFrameFor's.
Result<MeasureSource> LoadMeasureSource(Store& store, const std::string& name,
                                        SurfaceFilter filter);

// The store's CRS (nullopt before it has one) and its frame.
Result<std::pair<std::optional<Crs>, MetricFrame>> StoreFrame(Store& store);

// Polygons to measure inside. With `feature` != 0: that stored feature's polygons, looked up on
// each of `surfaces` in turn (NotFound "no feature 12 on surface 'a' or 'b'"; InvalidArgument
// for a breakline). Otherwise every polygon of every feature in the vector file `path`,
// reprojected to the store's CRS (ReadPolygonFeatures' errors). REQUIRES: exactly one of
// `feature` and `path` is set.
Result<std::vector<Polygon>> LoadMeasurePolygons(Store& store,
                                                 const std::vector<SurfaceInfo>& surfaces,
                                                 int64_t feature, const std::string& path);

}  // namespace tinbase
