#include "core/tin/region_outline.h"

namespace tinbase {

DirectedOutline::DirectedOutline(size_t vertices,
                                 const std::vector<std::pair<uint32_t, uint32_t>>& edges)
    : first_(vertices + 1, 0), to_(edges.size()) {
  for (const auto& [a, b] : edges) ++first_[a + 1];
  for (size_t v = 0; v < vertices; ++v) first_[v + 1] += first_[v];
  std::vector<uint32_t> next(first_.begin(), first_.end() - 1);
  for (const auto& [a, b] : edges) to_[next[a]++] = b;
}

bool DirectedOutline::Has(uint32_t a, uint32_t b) const {
  if (a + 1 >= first_.size()) return false;
  for (uint32_t k = first_[a]; k < first_[a + 1]; ++k)
    if (to_[k] == b) return true;
  return false;
}

std::vector<uint8_t> ClassifyInside(const Tin& tin, const DirectedOutline& outline) {
  constexpr uint8_t kUnknown = 2;
  std::vector<uint8_t> inside(tin.triangles.size(), kUnknown);
  std::vector<uint32_t> queue;
  for (uint32_t t = 0; t < tin.triangles.size(); ++t) {
    const auto& v = tin.triangles[t].v;
    for (int i = 0; i < 3 && inside[t] == kUnknown; ++i) {
      const uint32_t a = v[i], b = v[(i + 1) % 3];
      if (outline.Has(a, b))
        inside[t] = 1;
      else if (outline.Has(b, a))
        inside[t] = 0;
    }
    if (inside[t] != kUnknown) queue.push_back(t);
  }
  while (!queue.empty()) {
    const uint32_t t = queue.back();
    queue.pop_back();
    const TinTriangle& tri = tin.triangles[t];
    for (int i = 0; i < 3; ++i) {
      const int32_t n = tri.n[i];
      if (n == kNoNeighbour || inside[n] != kUnknown) continue;
      const uint32_t a = tri.v[(i + 1) % 3], b = tri.v[(i + 2) % 3];
      if (outline.Has(a, b) || outline.Has(b, a)) continue;
      inside[n] = inside[t];
      queue.push_back(static_cast<uint32_t>(n));
    }
  }
  for (uint8_t& c : inside)
    if (c == kUnknown) c = 0;
  return inside;
}

}  // namespace tinbase
