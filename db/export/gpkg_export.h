// GeoPackage export: a surface, or the part of it a SurfaceFilter selects, as an OGC GeoPackage
// written through GDAL's GPKG driver, so QGIS and every GDAL/OGR reader open it.
//
// Layers (names fixed, in the store's CRS):
//   triangles    Polygon Z, FID column `id` = the triangle's store id; n0, n1, n2 the store ids
//                of the neighbours across the edges opposite v0, v1, v2 (null on the boundary of
//                the selection); visible (0/1); tag (text, null when untagged).
//   features     MultiPolygon, FID `id` = the feature's store id; mode, tag, level and
//                attributes (JSON text) of the surface's polygon features that meet the
//                selection (with filter.feature: that feature alone).
//   breaklines   MultiLineString, the breakline features that meet the selection, same fields.
//   constraints  LineString Z, one per constrained edge whose two vertices are selected: va, vb
//                (vertex store ids) and the feature it belongs to (null for the surface's own).
//   dem          a Float32 2D gridded coverage (GDAL's GPKG raster, TIFF tiles) of the DEM cells
//                under the selection's box, nodata as the DEM declares it (else NaN); the
//                window is read into memory once (DemStore::ReadWindow) and handed to GDAL.
// The file is written under a temporary name and renamed into place (core/base/output_file.h),
// so a failed export leaves nothing at `path`. Thread-safety: one call per Store at a time.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "core/raster/grid_geometry.h"
#include "db/query/surface_selection.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

struct GpkgExportOptions {
  SurfaceFilter filter;
  // The DEM of the `dem` raster: empty = the surface's own DEM (no raster when it has none).
  std::string dem;
  bool with_dem = true;  // false: no raster layer at all
};

struct GpkgExportReport {
  int64_t triangles = 0;
  int64_t vertices = 0;
  int64_t features = 0;
  int64_t breaklines = 0;
  int64_t constraints = 0;
  std::string dem;                     // name of the DEM written, empty when none
  std::optional<GridGeometry> raster;  // its cells' geometry
};

// Writes the GeoPackage at `path` (replacing a file there only on success). Errors: SelectSurface's
// (NotFound naming the surface and the filter when nothing is selected); NotFound naming a DEM
// `options.dem` the store does not have; InvalidArgument when the DEM does not overlap the
// selection; IOError naming `path` when the directory is not writable or GDAL fails to write.
Result<GpkgExportReport> ExportGpkg(Store& store, const SurfaceInfo& surface,
                                    const GpkgExportOptions& options, const std::string& path);

}  // namespace tinbase
