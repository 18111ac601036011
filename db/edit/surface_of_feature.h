// The surface a feature belongs to, for the edits that are given only a feature id (points add
// onto a feature, polygon remove and update): they open their session on that surface.
#pragma once

#include <cstdint>

#include "core/base/status.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

// The surface that holds feature `id`; NotFound "no feature 12" when there is no such feature.
Result<SurfaceInfo> SurfaceOfFeature(Store& store, int64_t id);

}  // namespace tinbase
