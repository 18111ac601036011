// Edges of the stored mesh as pairs of store vertex ids, and a sorted table from edges to ids,
// shared by the stages of the edit path (db/edit/update_engine.h) and the edit writes of
// MeshTables (db/mesh/mesh_tables.h). Plain data; not synchronised.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace tinbase {

using MeshEdge = std::pair<int64_t, int64_t>;  // (min, max) store vertex ids, or a directed pair

inline MeshEdge EdgeKey(int64_t a, int64_t b) { return {std::min(a, b), std::max(a, b)}; }

struct MeshEdgeHash {
  size_t operator()(const MeshEdge& e) const {
    return std::hash<int64_t>()(e.first) * 1000003u ^ std::hash<int64_t>()(e.second);
  }
};

// Edges to ids, looked up by binary search: each edit builds a few once and reads them many
// times, and a hash map spent a heap node per entry.
class MeshEdgeTable {
 public:
  void Reserve(size_t n) { entries_.reserve(n); }
  void Add(const MeshEdge& e, int64_t id) { entries_.emplace_back(e, id); }
  // REQUIRES: called after the last Add and before the first Find.
  void Seal() { std::sort(entries_.begin(), entries_.end()); }
  // The id of edge `e`, or null.
  const int64_t* Find(const MeshEdge& e) const {
    auto it =
        std::lower_bound(entries_.begin(), entries_.end(), e,
                         [](const auto& entry, const MeshEdge& key) { return entry.first < key; });
    return it != entries_.end() && it->first == e ? &it->second : nullptr;
  }
  bool empty() const { return entries_.empty(); }

 private:
  std::vector<std::pair<MeshEdge, int64_t>> entries_;
};

}  // namespace tinbase
