// The tile pyramids a request may name. The store keeps at most one quantized-mesh pyramid per
// surface (db/tiles/tile_store.h); the API names it "default", so a client that lists a
// surface's pyramids and passes `?pyramid=NAME` keeps working when a surface may hold several.
// Thread-safety: as the Store.
#pragma once

#include <httplib.h>

#include <string>
#include <vector>

#include "core/base/status.h"
#include "db/store.h"
#include "db/surface_store.h"
#include "db/tiles/tile_store.h"

namespace tinbase::service {

inline constexpr const char* kDefaultPyramid = "default";

// The names of the surface's pyramids: {"default"} when it has tiles, else none.
Result<std::vector<std::string>> TilePyramidNames(Store& store, const SurfaceInfo& surface);

// The pyramid the request names with `?pyramid=` (or the surface's only one). NotFound
// "surface 's' has no tiles (...)" or "surface 's' has no tile pyramid 'p'".
Result<TilePyramidInfo> RequestedPyramid(Store& store, const SurfaceInfo& surface,
                                         const httplib::Request& req);

}  // namespace tinbase::service
