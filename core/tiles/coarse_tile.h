// Coarse tile: a tile of a level above the finest, made from its four children within the level's
// vertical error bound (docs/tiles.md, "Levels").
//
// A tile depends on its children alone, so after an edit it can be made again from them, and
// comes out byte for byte as a full build would make it. Its neighbours agree with it along their
// shared edges because the edge points are chosen from the edge alone: the children's vertices
// on the tile's edge (which the neighbour's children have too, being their neighbours), thinned
// by Douglas-Peucker within the bound. The inside is refined greedily
// (core/tin/tolerance_refiner.h) over a raster of the children until every raster cell is within
// the bound; triangles whose centroid falls where no child has a triangle are left out. Normals
// and water come from the children's. Pure functions.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/tiles/quantized_mesh.h"
#include "core/tiles/tiling_scheme.h"

namespace tinbase {

struct CoarseTileOptions {
  double error = 1;       // metres; > 0: the vertical error bound of the level
  double min_height = 0;  // the pyramid's quantisation range
  double max_height = 1;
  int raster = 257;  // cells across the tile the bound is measured on
};

// Tile `key` from its children, index dy * 2 + dx (dy = 0 the southern pair, dx = 0 the western),
// null where a child does not exist. nullopt when nothing of positive area is left.
std::optional<QuantizedMesh> MergeChildren(const std::array<const QuantizedMesh*, 4>& children,
                                           const TileKey& key, const CoarseTileOptions& options);

// The parent's water mask from its children's (a cell is water where any of the four child cells
// under it is), one byte when uniform.
std::vector<uint8_t> MergeWaterMasks(const std::array<const QuantizedMesh*, 4>& children);

}  // namespace tinbase
