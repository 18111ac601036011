// TileMeshBuilder: one quantized-mesh tile assembled from convex polygons that lie in the tile.
//
// Both the finest level's cutter (triangles clipped to the tile) and the coarser levels (a tile's
// simplified triangulation) hand their polygons here, so the rules that make neighbouring tiles
// agree live in one place: points that quantise to the same u, v are one vertex, the lowest of
// them (then the smallest normal), whatever order they come in; fans of zero quantised area are
// dropped; vertices on the tile's edges stay even when no triangle uses them; edge lists are
// sorted along the edge; heights quantise against the pyramid's one range.
// Not thread-safe; one per tile.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "core/tiles/quantized_mesh.h"
#include "core/tiles/tile_bounds.h"
#include "core/tiles/tiling_scheme.h"

namespace tinbase {

// A point of a polygon in the tile: longitude, latitude (degrees), height (metres) and an ECEF
// normal (ignored unless the builder makes normals; need not be unit length).
struct TilePoint {
  double lon = 0, lat = 0, h = 0;
  Ecef normal{};
};

// `value` in [lo, hi] as 0..kQuantizedMax, rounded to nearest (0 when hi <= lo).
uint16_t Quantise(double value, double lo, double hi);

class TileMeshBuilder {
 public:
  // `min_height`, `max_height`: the quantisation range of every tile of the pyramid.
  TileMeshBuilder(const TileRect& rect, double min_height, double max_height, bool normals);

  // A convex polygon, counter-clockwise, its points inside the tile's closed rectangle.
  void AddPolygon(const std::vector<TilePoint>& polygon);

  // A point that belongs to the tile even if no polygon uses it (it is kept when it lies on the
  // tile's edge, where the neighbour may use it).
  void AddPoint(const TilePoint& point) { VertexOf(point); }

  // The tile (vertices in first-use order, header bounds set); nullopt when no triangle of
  // positive area was added.
  std::optional<QuantizedMesh> Finish();

 private:
  uint32_t VertexOf(const TilePoint& p);
  void AddTriangle(uint32_t a, uint32_t b, uint32_t c);
  void DropUnused();
  void SortEdges();
  Ecef Position(size_t i) const;

  TileRect rect_;
  double min_height_;
  double max_height_;
  bool normals_wanted_;
  QuantizedMesh mesh_;
  std::vector<double> heights_;  // metres, per vertex, quantised when the tile is finished
  std::vector<Ecef> normals_;
  std::map<std::pair<uint16_t, uint16_t>, uint32_t> index_;
};

}  // namespace tinbase
