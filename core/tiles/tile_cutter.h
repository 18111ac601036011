// TileCutter: the quantized-mesh tiles of one level, cut from one TIN in geographic coordinates.
//
// Crack-free by construction (docs/tiles.md): every point a tile puts on its edge is computed
// from the TIN alone, never from the tile, so the tile on the other side computes the same one:
//   - where a TIN edge crosses a tile edge, the point is interpolated along the TIN edge from its
//     lower-numbered end, and its coordinate on the tile edge is set to the tile edge exactly;
//   - a tile corner takes its height from the lowest-numbered visible triangle that holds it;
//   - heights are quantised against one range for the whole pyramid (GeoSurface), not per tile,
//     so equal heights quantise equally; u and v against the tile's bounds, which neighbours
//     share bit for bit (core/tiles/tiling_scheme.h).
// Invisible triangles are left out (a client sees a hole). Vertex normals come from the whole
// surface (GeoSurface::normals), so shading has no seams at tile edges.
// Thread-safety: Cut is const and may run on several tiles at once.
#pragma once

#include <map>
#include <optional>
#include <vector>

#include "core/base/status.h"
#include "core/tiles/quantized_mesh.h"
#include "core/tiles/tile_bounds.h"
#include "core/tiles/tiling_scheme.h"
#include "core/tin/tin.h"

namespace tinbase {

// A TIN ready to be tiled: x longitude and y latitude in degrees, z metres above the ellipsoid,
// triangles counter-clockwise with their visibility.
struct GeoSurface {
  Tin tin;
  std::vector<Ecef> normals;  // unit ECEF normal per vertex; empty for no normals
  double min_height = 0;      // the quantisation range of every tile of the pyramid
  double max_height = 0;
};

// Area-weighted unit vertex normals of `tin` (geographic, as GeoSurface) in ECEF, from the
// triangles' true 3D shape on the ellipsoid, visible or not.
std::vector<Ecef> VertexNormals(const Tin& tin);

class TileCutter {
 public:
  // REQUIRES: `surface` outlives the cutter; 0 <= level <= kMaxTileLevel.
  TileCutter(const GeoSurface& surface, int level);

  // The tiles whose closed rectangle a visible triangle's bounding box meets, in key order: every
  // tile with content is among them (Cut may still find none in a tile the box only touched).
  std::vector<TileKey> Tiles() const;

  // The tile `key` (vertices in first-use order, edge lists sorted along the edge, normals when
  // the surface has them); nullopt when no visible triangle meets it.
  std::optional<QuantizedMesh> Cut(const TileKey& key) const;

  // The tile's water mask (the extension's layout): 256 x 256 bytes, rows north to south, 255
  // where a cell centre lies in a visible triangle tagged `water_tag` (an index into the tin's
  // tags), else 0; a single byte when every cell is the same.
  std::vector<uint8_t> WaterMask(const TileKey& key, int32_t water_tag) const;

 private:
  const GeoSurface& surface_;
  std::vector<TinVertex> vertices_;  // the surface's, snapped onto the level's tile lines
  std::map<TileKey, std::vector<uint32_t>> triangles_of_tile_;
};

}  // namespace tinbase
