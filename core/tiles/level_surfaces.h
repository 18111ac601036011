// Level surfaces: the surface (or the window of it) a tile pyramid's finest level is cut from,
// in longitude/latitude, and the finest level a pyramid needs (docs/tiles.md, "Levels"). The
// coarser levels are made from the finest (core/tiles/coarse_tile.h). Pure functions.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/tiles/tile_cutter.h"
#include "core/tin/tin.h"

namespace tinbase {

// `tin` (of `crs`) with x longitude, y latitude (degrees, WGS 84) and z in metres, the vertex
// normals when `normals`, and the height range [min_height, max_height] the pyramid quantises
// against. InvalidArgument naming the CRS when it cannot be transformed to EPSG:4326.
Result<GeoSurface> GeographicSurface(const Tin& tin, const Crs& crs, bool normals,
                                     double min_height, double max_height);

// The level at which one tile holds about 128 of `tin`'s mean vertex spacings across (the
// finest level a pyramid needs), from 0 to kMaxTileLevel.
int NaturalMaxZoom(const GeoSurface& surface);
// The same from the surface's geographic box (degrees) and vertex count.
int NaturalMaxZoom(double west, double south, double east, double north, size_t vertices);

}  // namespace tinbase
