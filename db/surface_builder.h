// SurfaceBuilder: builds a terrain surface from a stored DEM and writes it in one transaction.
//
// Runs a core TIN builder on the DEM (greedy streams it block by block, so its DEM may be larger
// than memory; the others read the level-0 grid into memory) and writes
// vertices, triangles, neighbour links, visibility, blocks and a `changes` row together: on any
// error nothing is written. Builders, by `method` (core/tin/terrain_builder.h TerrainMethod; the
// surface's `method` column records its canonical spelling):
//   greedy    greedy insertion to a vertical tolerance (core/tin/greedy_builder.h); a
//             `delaunay` surface.
//   vip       very important points (core/tin/vip_builder.h) above a threshold, Delaunay; no
//             error bound, so its tolerance is the largest |TIN - DEM| measured.
//   rtin      the binary triangle tree (core/tin/rtin_builder.h) with a true error bound; a
//             `free` surface.
//   collapse  the grid triangulation of the DEM, edge-collapsed to a face budget
//             (core/tin/edge_collapse.h); a `free` surface whose tolerance is the largest
//             |TIN - DEM| it keeps.
// Thread-safety: through one Store.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "core/base/status.h"
#include "core/tin/edge_collapse.h"
#include "core/tin/greedy_builder.h"
#include "core/tin/terrain_builder.h"
#include "db/dem_store.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

struct SurfaceBuildOptions {
  std::string surface;  // new surface name
  std::string dem;      // DEM name; empty: the store's only DEM
  TerrainMethod method = TerrainMethod::kGreedy;
  GreedyOptions greedy;        // tolerance (greedy, rtin) and max_points (greedy, vip)
  double vip_threshold = 1.0;  // vip: the significance threshold in metres
  CollapseOptions collapse;    // for collapse
  // Called with the fraction done after each stage (the TIN built, its rows written), from the
  // calling thread; empty: not called. The builders do not report from inside yet.
  std::function<void(double fraction)> progress;
};

struct SurfaceBuildReport {
  SurfaceInfo surface;
  GreedyReport quality;     // max and RMS |TIN - DEM| for every method; points for greedy
  CollapseReport collapse;  // for collapse
  int64_t vertices = 0;
  int64_t triangles = 0;
  int64_t tx = 0;
  double build_seconds = 0;
  double write_seconds = 0;
};

// Picks the DEM by name, or the only DEM when `name` is empty (InvalidArgument listing the
// choices when there are several, NotFound when there is none).
Result<DemInfo> ResolveDem(DemStore& dems, const std::string& name);

// Conflict when the surface name is taken; InvalidArgument for bad options; Corruption or IOError
// naming the DEM block when a block the builder needs cannot be read (never taken for nodata).
Result<SurfaceBuildReport> BuildSurfaceFromDem(Store& store, const SurfaceBuildOptions& options);

}  // namespace tinbase
