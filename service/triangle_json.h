// The triangle object of the API (docs/api.md, "Triangles"): {"id", "vertices": [[x, y, z] x3],
// "lonlat": [[lon, lat, h] x3] (null when the store has no CRS), "neighbours": [id|null x3],
// "visible", "tag"}. neighbours[i] lies across the edge opposite vertices[i]; null on the
// surface's boundary. Thread-safety: as the Store read.
#pragma once

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/tin/tin.h"
#include "db/query/topology.h"
#include "db/store.h"
#include "db/surface_store.h"
#include "service/client_crs.h"

namespace tinbase::service {

// One stored triangle as the API shows it.
struct TriangleView {
  int64_t id = 0;
  std::array<TinVertex, 3> corners;  // counter-clockwise in plan view
  std::array<std::optional<int64_t>, 3> neighbours;
  bool visible = true;
  std::optional<std::string> tag;
};

// The view of a triangle NeighboursOf read.
TriangleView ViewOf(const TriangleNeighbours& t);

// The views of a selection's triangles (db/query/surface_selection.h). SelectSurface cuts the
// links across the selection's edge; those are read back from the store, so a neighbour outside
// the selection is its id, not null. REQUIRES: `selected` was read in the caller's snapshot.
Result<std::vector<TriangleView>> ViewsOf(Store& store, const SurfaceInfo& surface,
                                          const LoadedSurface& selected);

// The triangle objects of `views`, in order, with lon/lat when `store_crs` is not null.
// InvalidArgument naming the vertex when a corner does not transform to lon/lat.
Result<nlohmann::json> TrianglesJson(const std::vector<TriangleView>& views,
                                     const StoreCrs* store_crs);

}  // namespace tinbase::service
