// The JSON of a surface as `tinbase info --json` lists it.
#include "db/surface_json.h"

namespace tinbase {

nlohmann::json SurfaceSummaryJson(const SurfaceInfo& surface, const SurfaceCounts& counts) {
  nlohmann::json j = {{"name", surface.name},
                      {"kind", SurfaceKindName(surface.kind)},
                      {"method", surface.method},
                      {"vertices", counts.vertices},
                      {"triangles", counts.triangles},
                      {"visible_triangles", counts.visible_triangles},
                      {"constraints", counts.constraints},
                      {"features", counts.features}};
  j["tolerance"] = surface.tolerance ? nlohmann::json(*surface.tolerance) : nlohmann::json(nullptr);
  return j;
}

}  // namespace tinbase
