#include "db/dem_import_checks.h"

#include "db/surface_store.h"

namespace tinbase {

Status TooManyDemImportCells(const std::string& what, int64_t limit) {
  return Status::InvalidArgument(what + ", more than the limit of " + std::to_string(limit) +
                                 " cells for one import: check the rasters' sizes, or pass "
                                 "--force to import anyway");
}

Status CheckDemImportCells(const std::vector<GdalRaster>& rasters, int64_t limit) {
  if (limit <= 0) return Status::Ok();
  int64_t cells = 0;
  for (const GdalRaster& r : rasters) {
    const GridGeometry& g = r.geometry();
    // Each side fits GDAL's int, so one raster's count fits int64; the sum stops at the limit.
    cells += g.CellCount();
    if (cells > limit)
      return TooManyDemImportCells(r.path() + " claims " + std::to_string(g.width) + " x " +
                                       std::to_string(g.height) + " cells",
                                   limit);
  }
  return Status::Ok();
}

Status RefuseImportUnderSurfaces(Store& store, const DemInfo& dem) {
  TB_ASSIGN_OR_RETURN(const std::vector<SurfaceInfo> surfaces, SurfaceStore(store).List());
  std::string names;
  int count = 0;
  for (const SurfaceInfo& s : surfaces)
    if (s.dem == dem.id) names += (count++ == 0 ? "'" : ", '") + s.name + "'";
  if (count == 0) return Status::Ok();
  return Status::Conflict(
      "DEM '" + dem.name + "' has " +
      (count == 1 ? "a surface" : std::to_string(count) + " surfaces") + " built on it (" + names +
      "): importing into it would change the ground under " + (count == 1 ? "it" : "them") +
      "; import the sheets as a new DEM with --name");
}

}  // namespace tinbase
