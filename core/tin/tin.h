// Tin: an in-memory triangulated irregular network in the store's table layout.
//
// This is what builders produce and exporters consume, and what db/ writes to and reads from the
// store: vertices, triangles as three vertex indices counter-clockwise, and per triangle the
// neighbour across the edge opposite each vertex (kNoNeighbour on the domain boundary), as in the
// V and T arrays of paper 000. Indices are positions in the vectors, not store ids. Plain data;
// not synchronised.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace tinbase {

enum class VertexKind { kDem, kLidar, kRing, kSteiner, kUser };

// Store spelling of a VertexKind ("dem", "lidar", ...).
const char* VertexKindName(VertexKind kind);
// False when `name` is not one of the store spellings.
bool ParseVertexKind(const std::string& name, VertexKind* kind);

struct TinVertex {
  double x = 0;
  double y = 0;
  double z = 0;
  VertexKind kind = VertexKind::kDem;
};

inline constexpr int32_t kNoNeighbour = -1;
inline constexpr int32_t kNoTag = -1;

struct TinTriangle {
  std::array<uint32_t, 3> v{};  // counter-clockwise in plan view
  std::array<int32_t, 3> n{kNoNeighbour, kNoNeighbour, kNoNeighbour};  // n[i] opposite v[i]
  bool visible = true;
  int32_t tag = kNoTag;  // index into Tin::tags, or kNoTag
};

struct Tin {
  std::vector<TinVertex> vertices;
  std::vector<TinTriangle> triangles;
  // Constrained edges as vertex index pairs (each pair once, any order).
  std::vector<std::pair<uint32_t, uint32_t>> constraints;
  // Tag values (e.g. formation names) that triangles refer to by index.
  std::vector<std::string> tags;
};

// Recomputes every TinTriangle::n from the vertex indices alone: two triangles are neighbours
// when they share an edge in opposite directions. Returns false if an edge is used by more than
// two triangles or twice in the same direction, or a vertex index is out of range (the input is
// then not a valid triangulation). Linear time.
bool LinkNeighbours(Tin& tin);

}  // namespace tinbase
