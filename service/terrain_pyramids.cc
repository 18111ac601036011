// Naming a surface's tile pyramids.
#include "service/terrain_pyramids.h"

#include "service/request_params.h"

namespace tinbase::service {

Result<TilePyramidInfo> RequestedPyramid(Store& store, const SurfaceInfo& surface,
                                         const httplib::Request& req) {
  TB_ASSIGN_OR_RETURN(const std::optional<TilePyramidInfo> pyramid,
                      TileStore(store.db()).Pyramid(surface.id));
  if (!pyramid)
    return Status::NotFound("surface '" + surface.name +
                            "' has no tiles (build them with tinbase tiles build)");
  const std::optional<std::string> name = OptionalParam(req, "pyramid");
  if (name && *name != surface.name)
    return Status::NotFound("surface '" + surface.name + "' has no tile pyramid '" + *name +
                            "' (it has: " + surface.name + ")");
  return *pyramid;
}

}  // namespace tinbase::service
