#include "core/tin/tin.h"

#include <cstdint>
#include <vector>

namespace tinbase {

const char* VertexKindName(VertexKind kind) {
  switch (kind) {
    case VertexKind::kDem:
      return "dem";
    case VertexKind::kLidar:
      return "lidar";
    case VertexKind::kRing:
      return "ring";
    case VertexKind::kSteiner:
      return "steiner";
    case VertexKind::kUser:
      return "user";
  }
  return "dem";
}

bool ParseVertexKind(const std::string& name, VertexKind* kind) {
  for (VertexKind k : {VertexKind::kDem, VertexKind::kLidar, VertexKind::kRing,
                       VertexKind::kSteiner, VertexKind::kUser}) {
    if (name == VertexKindName(k)) {
      *kind = k;
      return true;
    }
  }
  return false;
}

bool LinkNeighbours(Tin& tin) {
  // Half-edges grouped by their first vertex (a counting sort), so the twin of (a, b) is found
  // in b's short list: linear time and memory, no hash map.
  struct HalfEdge {
    uint32_t b;
    int32_t triangle;
  };
  const size_t vertex_count = tin.vertices.size();
  std::vector<uint32_t> first(vertex_count + 1, 0);
  for (const TinTriangle& tri : tin.triangles) {
    for (uint32_t v : tri.v) {
      if (v >= vertex_count) return false;
      ++first[v + 1];  // each corner starts one half-edge of its triangle
    }
  }
  for (size_t v = 0; v < vertex_count; ++v) first[v + 1] += first[v];
  std::vector<HalfEdge> edges(first[vertex_count]);
  std::vector<uint32_t> next(first.begin(), first.end() - 1);
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const auto& v = tin.triangles[t].v;
    for (int i = 0; i < 3; ++i)
      edges[next[v[(i + 1) % 3]]++] = HalfEdge{v[(i + 2) % 3], static_cast<int32_t>(t)};
  }
  const auto find = [&](uint32_t a, uint32_t b) -> const HalfEdge* {
    for (uint32_t k = first[a]; k < first[a + 1]; ++k)
      if (edges[k].b == b) return &edges[k];
    return nullptr;
  };
  // A directed edge in two triangles: not a manifold, consistently oriented mesh.
  for (size_t a = 0; a < vertex_count; ++a)
    for (uint32_t k = first[a]; k < first[a + 1]; ++k)
      for (uint32_t j = k + 1; j < first[a + 1]; ++j)
        if (edges[k].b == edges[j].b) return false;
  for (TinTriangle& tri : tin.triangles) {
    for (int i = 0; i < 3; ++i) {
      const HalfEdge* twin = find(tri.v[(i + 2) % 3], tri.v[(i + 1) % 3]);
      tri.n[i] = twin != nullptr ? twin->triangle : kNoNeighbour;
    }
  }
  return true;
}

}  // namespace tinbase
