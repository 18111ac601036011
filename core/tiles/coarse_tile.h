// Coarse tile: a tile of a level above the finest, simplified from the finest surface clipped to
// the tile, within the level's vertical error bound (docs/tiles.md, "Levels").
//
// A tile is made from its own part of the surface alone, so it can be rebuilt on its own after an
// edit and comes out byte for byte as a full build would make it. Its neighbours agree with it
// along their shared edges because the edge points are chosen from the edge alone: the finest
// cut's vertices on each edge (which the neighbour's cut has too), thinned by Douglas-Peucker
// within the error bound. The inside is refined greedily (core/tin/tolerance_refiner.h) over a
// raster of the finest cut until every raster cell is within the bound; triangles whose centroid
// falls where the finest surface has no triangle are left out. Normals come from the finest
// surface's, interpolated. Pure function.
#pragma once

#include <optional>

#include "core/tiles/quantized_mesh.h"
#include "core/tiles/tiling_scheme.h"

namespace tinbase {

struct CoarseTileOptions {
  double error = 1;       // metres; > 0: the vertical error bound of the level
  double min_height = 0;  // the pyramid's quantisation range
  double max_height = 1;
  int raster = 257;  // cells across the tile the bound is measured on
};

// The simplified tile `key` from `finest_cut` (the finest surface clipped to this tile at this
// level's quantisation: TileCutter::Cut). nullopt when nothing of positive area is left.
std::optional<QuantizedMesh> SimplifyTile(const QuantizedMesh& finest_cut, const TileKey& key,
                                          const CoarseTileOptions& options);

}  // namespace tinbase
