// The features a mesh export describes (core/export/export_feature.h) read from a store: every
// feature of the surface as an ExportFeature, and which one each triangle of the exported Tin
// belongs to. `tinbase export` and the service's export route share it. Thread-safety: through
// one Store.
#pragma once

#include "core/base/status.h"
#include "core/export/tin_export.h"
#include "core/tin/tin.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

// Fills options.features (the surface's features in id order) and options.triangle_feature
// (one entry per triangle of `tin`). Errors: LoadFeatures'.
Status AddExportFeatures(Store& store, const SurfaceInfo& surface, const Tin& tin,
                         ExportOptions& options);

}  // namespace tinbase
