// QuantizedMesh: one terrain tile in Cesium's quantized-mesh-1.0 format, in memory, and its
// byte encoding (little-endian; header, zig-zag delta vertices, high-water-mark indices, edge
// vertex lists, extensions).
//
// The codec knows nothing of tiling or of where the numbers come from: the tile builder fills
// the header (centre, bounding sphere, horizon occlusion point) and the quantised vertices; the
// decoder checks every count against the bytes it has before it reads, so a truncated or hostile
// tile is an error naming the part and the byte offset, never a read past the end.
// Plain data; thread-safety as any value.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"

namespace tinbase {

inline constexpr int kQuantizedMax = 32767;  // u, v and heights run 0..32767

struct QuantizedMeshHeader {
  double center_x = 0, center_y = 0, center_z = 0;  // ECEF metres, the tile's centre
  float min_height = 0, max_height = 0;             // metres above the ellipsoid
  double sphere_x = 0, sphere_y = 0, sphere_z = 0, sphere_radius = 0;  // ECEF bounding sphere
  // The horizon occlusion point in the ellipsoid's scaled space (ECEF divided by the radii).
  double horizon_x = 0, horizon_y = 0, horizon_z = 0;
  friend bool operator==(const QuantizedMeshHeader&, const QuantizedMeshHeader&) = default;
};

struct QuantizedMesh {
  QuantizedMeshHeader header;
  // Per vertex: u west to east, v south to north, height min to max, each 0..kQuantizedMax.
  std::vector<uint16_t> u, v, height;
  // Counter-clockwise triangles, three vertex indices each. Vertices must be numbered in order
  // of first use in this list (what high-water-mark encoding needs): OrderVerticesByFirstUse.
  std::vector<uint32_t> triangles;
  // The vertices on each edge of the tile.
  std::vector<uint32_t> west, south, east, north;
  // Extension 1: two bytes per vertex, the oct-encoded unit normal.
  std::optional<std::vector<uint8_t>> normals;
  // Extension 2: one byte (0 land, 255 water, for the whole tile) or 256 x 256 bytes, rows
  // north to south.
  std::optional<std::vector<uint8_t>> water_mask;
  // Extension 4: a JSON object (as text), e.g. {"available": [...]}.
  std::optional<std::string> metadata;

  size_t vertex_count() const { return u.size(); }
  friend bool operator==(const QuantizedMesh&, const QuantizedMesh&) = default;
};

// The bytes of `mesh` (not gzipped). InvalidArgument naming the problem when the arrays
// disagree in length, an index is out of range, the vertices are not in first-use order, or an
// extension has the wrong size.
Result<std::vector<uint8_t>> EncodeQuantizedMesh(const QuantizedMesh& mesh);

// Reads a tile. InvalidArgument naming `source`, the part being read and the byte offset when
// the bytes are too short, a count does not fit what is left, an index is out of range, or an
// extension is malformed. Unknown extensions are skipped, as Cesium does.
Result<QuantizedMesh> DecodeQuantizedMesh(const std::vector<uint8_t>& bytes,
                                          const std::string& source);

// Renumbers the vertices of `mesh` in order of first use by its triangles (edge lists and
// normals follow); vertices no triangle uses go last.
void OrderVerticesByFirstUse(QuantizedMesh& mesh);

// Oct-encodes a unit normal into two bytes (and back), as the vertex-normals extension stores it.
void OctEncodeNormal(double x, double y, double z, uint8_t* out);
void OctDecodeNormal(const uint8_t* in, double* x, double* y, double* z);

}  // namespace tinbase
