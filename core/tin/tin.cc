#include "core/tin/tin.h"

#include <unordered_map>

namespace tinbase {

const char* VertexKindName(VertexKind kind) {
  switch (kind) {
    case VertexKind::kDem: return "dem";
    case VertexKind::kLidar: return "lidar";
    case VertexKind::kRing: return "ring";
    case VertexKind::kSteiner: return "steiner";
    case VertexKind::kUser: return "user";
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
  // Directed edge (a, b) -> (triangle, index of the vertex opposite it).
  std::unordered_map<uint64_t, std::pair<int32_t, int>> half_edges;
  half_edges.reserve(tin.triangles.size() * 3);
  const auto key = [](uint32_t a, uint32_t b) { return (uint64_t{a} << 32) | b; };
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    auto& tri = tin.triangles[t];
    tri.n = {kNoNeighbour, kNoNeighbour, kNoNeighbour};
    for (int i = 0; i < 3; ++i) {
      const uint32_t a = tri.v[(i + 1) % 3];
      const uint32_t b = tri.v[(i + 2) % 3];
      if (!half_edges.emplace(key(a, b), std::make_pair(static_cast<int32_t>(t), i)).second)
        return false;
    }
  }
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    auto& tri = tin.triangles[t];
    for (int i = 0; i < 3; ++i) {
      const uint32_t a = tri.v[(i + 1) % 3];
      const uint32_t b = tri.v[(i + 2) % 3];
      auto it = half_edges.find(key(b, a));
      if (it != half_edges.end()) tri.n[i] = it->second.first;
    }
  }
  return true;
}

}  // namespace tinbase
