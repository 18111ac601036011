// The tile pyramids a request may name. The store keeps at most one quantized-mesh pyramid per
// surface (db/tiles/tile_store.h); the API names it after the surface (as GET /surfaces lists
// it), so a client that passes `?pyramid=NAME` keeps working when a surface may hold several.
// Thread-safety: as the Store.
#pragma once

#include <httplib.h>

#include <string>

#include "core/base/status.h"
#include "db/store.h"
#include "db/surface_store.h"
#include "db/tiles/tile_store.h"

namespace tinbase::service {

// The pyramid the request names with `?pyramid=` (or the surface's only one). NotFound
// "surface 's' has no tiles (...)" or "surface 's' has no tile pyramid 'p'".
Result<TilePyramidInfo> RequestedPyramid(Store& store, const SurfaceInfo& surface,
                                         const httplib::Request& req);

}  // namespace tinbase::service
