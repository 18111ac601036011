// ExportTin: one entry point for every surface file format (core/export/export_format.h). It
// picks the triangles (MeshSelection), hands them to the format's writer (one file per format
// in core/export/) and writes through OutputFile, so a failed export leaves no file behind and
// a successful one replaces the target in one rename. Thread-safety: pure function.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/export/export_feature.h"
#include "core/export/export_format.h"
#include "core/geometry/crs.h"
#include "core/tin/tin.h"

namespace tinbase {

struct ExportOptions {
  ExportFormat format = ExportFormat::kObj;
  bool visible_only = false;
  std::vector<int64_t> triangle_ids;  // store ids for GeoJSON properties (optional)
  // GLB only: the features and each triangle's feature (core/export/glb_writer.h GlbContent);
  // triangle_feature is empty or has one entry per triangle.
  std::vector<ExportFeature> features;
  std::vector<int32_t> triangle_feature;
};

struct ExportReport {
  int64_t vertices = 0;
  int64_t triangles = 0;
  int64_t bytes = 0;  // of the written file
};

// Writes `tin` to `path` in options.format; `crs` may be null. IOError naming the path when it
// cannot be written (its directory missing or not writable); InvalidArgument when the ids do not
// match the triangles or nothing is left to write. On any error no file is left at `path` (and an
// earlier file there is untouched).
Result<ExportReport> ExportTin(const Tin& tin, const Crs* crs, const std::string& path,
                               const ExportOptions& options);

}  // namespace tinbase
