// Surface exporters: write a Tin to the files clients read.
//
// OBJ (Wavefront: `v x y z` and 1-based `f a b c`, counter-clockwise seen from above) and GeoJSON
// (a FeatureCollection of 3D Polygon features, one per triangle, with id/visible/tag properties,
// written through OGR's GeoJSON driver so the CRS is declared as GDAL does). `visible_only` drops
// invisible triangles (and vertices no longer used). Thread-safety: pure functions.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/tin/tin.h"

namespace tinbase {

enum class ExportFormat { kObj, kGeoJson };
// "obj" / "geojson"; InvalidArgument naming the format otherwise.
Result<ExportFormat> ParseExportFormat(const std::string& name);

struct ExportOptions {
  ExportFormat format = ExportFormat::kObj;
  bool visible_only = false;
  std::vector<int64_t> triangle_ids;  // store ids for GeoJSON properties (optional)
};

struct ExportReport {
  int64_t vertices = 0;
  int64_t triangles = 0;
};

// Writes `tin` to `path`; IOError naming the path when it cannot be written.
Result<ExportReport> ExportTin(const Tin& tin, const Crs* crs, const std::string& path,
                               const ExportOptions& options);

}  // namespace tinbase
