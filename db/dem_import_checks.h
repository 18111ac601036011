// What a DEM import checks before it reads a cell (db/dem_store.h, DemStore::Import): the
// number of cells the sources claim against the import's limit, and that no surface stands on
// the DEM it would change. Thread-safety: as the Store passed in.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/raster/gdal_raster.h"
#include "db/dem_store.h"
#include "db/store.h"

namespace tinbase {

// InvalidArgument "<what>, more than the limit of <limit> cells for one import: ... --force".
Status TooManyDemImportCells(const std::string& what, int64_t limit);

// Ok when the rasters' headers claim at most `limit` cells in all (0: no limit); otherwise
// TooManyDemImportCells naming the raster that passes the limit and its claimed size.
Status CheckDemImportCells(const std::vector<GdalRaster>& rasters, int64_t limit);

// Ok when no surface is built on `dem`; Conflict naming them otherwise: importing into the DEM
// would change the ground under them, and their tolerance would no longer hold.
Status RefuseImportUnderSurfaces(Store& store, const DemInfo& dem);

}  // namespace tinbase
