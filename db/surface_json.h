// The JSON of a surface as `tinbase info --json` lists it (name, kind, method, counts,
// tolerance), shared by the CLI and the service's GET /surfaces so the two never drift apart.
// Thread-safety: a pure function.
#pragma once

#include <nlohmann/json.hpp>

#include "db/surface_store.h"

namespace tinbase {

nlohmann::json SurfaceSummaryJson(const SurfaceInfo& surface, const SurfaceCounts& counts);

}  // namespace tinbase
