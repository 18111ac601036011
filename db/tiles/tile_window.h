// Tile window: the part of a stored surface that the finest tiles inside one longitude/latitude
// rectangle are cut from, read without loading the rest (docs/tiles.md, "Windows").
//
// A finest tile depends on the triangles whose (snapped) geographic bounding box meets it, taken
// in store id order, and on the vertex normals of their vertices, each summed over all the
// triangles around the vertex in id order. So the window holds exactly what makes the cut equal
// to a cut of the whole surface: every triangle whose geographic box meets the rectangle (grown
// by one quantisation step of the level, more than the snapping moves a vertex), every triangle
// around one of their vertices, and their vertices; triangles and vertices in store id order.
// It may hold a few more triangles, which no tile of the rectangle uses.
//
// The reading seeds from the centroid blocks under the rectangle's image in the store's CRS and
// from the triangles holding its centre and corners, then walks across neighbours, as
// SelectSurface's window does (a large triangle can meet the window with its centroid elsewhere).
// Thread-safety: as the Store it reads.
#pragma once

#include <cstdint>
#include <utility>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/tiles/tiling_scheme.h"
#include "core/tin/tin.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

struct TileWindow {
  Tin tin;  // in the store's CRS; triangles and vertices in store id order; no neighbour links
  int64_t cut_triangles = 0;  // triangles whose geographic box meets the rectangle
  // The lowest and highest z of the window's vertices (store units); +inf/-inf when empty.
  double min_z = 0;
  double max_z = 0;
};

// The window of `surface` (whose store CRS is `crs`) for the finest tiles of `level` inside
// `rect` (degrees). InvalidArgument when the CRS has no transformation to EPSG:4326; Corruption
// for a triangle linked to a missing vertex. REQUIRES: a snapshot or transaction held around it.
Result<TileWindow> ReadTileWindow(Store& store, const SurfaceInfo& surface, const Crs& crs,
                                  const TileRect& rect, int level);

// The rectangle covered by the tiles of a range (the union of their rectangles).
TileRect RectOfRange(const TileRange& range);

}  // namespace tinbase
