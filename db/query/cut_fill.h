// Cut and fill: the volume between two stored surfaces (existing ground and a design, or a
// formation's base and top), over their common visible part or inside a polygon, through
// VolumeBetween (core/measure/volume.h). Thread-safety: as the Store it reads.
#pragma once

#include <cstdint>
#include <string>

#include "core/base/status.h"
#include "core/measure/volume.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

struct CutFillRequest {
  std::string base;          // existing ground
  std::string top;           // the design
  int64_t feature = 0;       // measure inside this stored polygon feature (of either surface)
  std::string polygon_file;  // or inside the polygons of this vector file
};

struct CutFillResult {
  SurfaceInfo base, top;
  bool inside_polygon = false;
  // split.above_volume: fill (top above base); split.below_volume: cut (top below base).
  VolumeReport volume;
};

// Errors: NotFound for an unknown surface, feature or file; InvalidArgument when both a feature
// and a file are given, for a bad polygon (LoadMeasurePolygons), or "surfaces 'a' and 'b' do not
// overlap" (with " inside the polygon" when one is given) when their visible parts share no
// plan area there.
Result<CutFillResult> CutFill(Store& store, const CutFillRequest& request);

}  // namespace tinbase
