// Level surfaces: the TIN each level of a tile pyramid is cut from (docs/tiles.md, "Levels").
//
// The finest level is the stored surface itself, with its constraints, visibility and tags. Each
// coarser level is a greedy TIN of the finest one, rasterised, within a vertical error bound
// that doubles per level up (halves per level down): the bound is measured against the finest
// surface at every raster cell, so it is a true bound, not a face budget. Parts the finest level
// hides (clip, erase) are nodata in the raster, so coarser levels hide them too.
// GeographicSurface turns a TIN of the store's CRS into the longitude/latitude form tiles are cut
// from. Pure functions.
#pragma once

#include <cstdint>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/raster/grid_geometry.h"
#include "core/tiles/tile_cutter.h"
#include "core/tin/tin.h"

namespace tinbase {

// The raster a surface is measured on for its coarser levels: its plan box, with cells sized so
// there are about four per vertex, and at most `max_cells` cells.
GridGeometry LevelRaster(const Tin& tin, int64_t max_cells = int64_t{1} << 24);

// A TIN within `tolerance` (metres) of `tin`'s visible triangles at every cell of `raster`;
// triangles over hidden parts are invisible. InvalidArgument when `tolerance` is not positive or
// no visible triangle covers a cell.
Result<Tin> CoarserTin(const Tin& tin, const GridGeometry& raster, double tolerance);

// `tin` (of `crs`) with x longitude, y latitude (degrees, WGS 84) and z in metres, the vertex
// normals when `normals`, and the height range [min_height, max_height] the pyramid quantises
// against. InvalidArgument naming the CRS when it cannot be transformed to EPSG:4326.
Result<GeoSurface> GeographicSurface(const Tin& tin, const Crs& crs, bool normals,
                                     double min_height, double max_height);

// The lowest and highest z of `tin`'s vertices, converted to metres.
std::pair<double, double> HeightRange(const Tin& tin, const Crs& crs);

// The level at which one tile holds about 128 of `tin`'s mean vertex spacings across (the
// finest level a pyramid needs), from 0 to kMaxTileLevel.
int NaturalMaxZoom(const GeoSurface& surface);

}  // namespace tinbase
