// The TIN of a DEM window reduced to a face budget (paper 002's web 3D-GIS step): the window's
// cells at the sampling step a cell budget allows (DemStore::ClipLevel), their full grid
// triangulation (core/tin/grid_triangulation.h), then edge collapse to the face budget
// (core/tin/edge_collapse.h) with the window's cells as the reference for the error. What
// `tinbase dem clip --faces N --format glb` writes and `GET /dems/{d}/tin` serves.
// Thread-safety: as DemStore (one per thread).
#pragma once

#include <cstdint>

#include "core/base/status.h"
#include "core/raster/grid_geometry.h"
#include "core/tin/edge_collapse.h"
#include "core/tin/tin.h"
#include "db/dem_store.h"

namespace tinbase {

struct DemWindowTinOptions {
  int64_t max_cells = 1024 * 1024;  // read the finest level whose window has at most this many
  int64_t faces = 0;                // face budget of the edge collapse; 0: no collapse
  CollapseStrategy strategy = CollapseStrategy::kGarlandHeckbert;
};

struct DemWindowTin {
  Tin tin;
  int level = 0;            // the overview level the cells came from
  GridGeometry geometry;    // of the window read
  CollapseReport collapse;  // faces_in/out are the grid's when there was no collapse
};

// The reduced TIN of `box`. Errors of DemStore::ReadWindow (box outside the DEM, ...);
// NotFound when the window holds no complete square of valid cells; InvalidArgument for a face
// budget of 1 or less than 0.
Result<DemWindowTin> BuildDemWindowTin(DemStore& dems, const DemInfo& dem, const DemBox& box,
                                       const DemWindowTinOptions& options);

}  // namespace tinbase
