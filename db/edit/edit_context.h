// What every stage of an edit reads through (db/edit/update_engine.h): the store, the surface and
// its DEM, and the mesh rows (db/mesh_cache.h). Borrowed references, valid for one Apply; not
// thread-safe.
#pragma once

#include <algorithm>
#include <cmath>

#include "db/dem_store.h"
#include "db/mesh_cache.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

struct EditContext {
  Store& store;
  const SurfaceInfo& surface;
  DemStore& dems;
  const DemInfo& dem;
  MeshCache& mesh;

  // The larger DEM cell edge.
  double Cell() const { return std::max(dem.geometry.cell_x, std::fabs(dem.geometry.cell_y)); }
};

}  // namespace tinbase
