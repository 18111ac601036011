// The crack test of quantized-mesh pyramids: every pair of neighbouring tiles of one level must
// list the same vertices, at the same quantised positions and heights, along their shared edge.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include "core/tiles/quantized_mesh.h"
#include "core/tiles/tiling_scheme.h"

namespace tinbase::testing {

struct EdgePoint {
  uint16_t along;
  uint16_t height;
  // NOLINTNEXTLINE(modernize-use-nullptr): a false finding on a defaulted <=>
  friend auto operator<=>(const EdgePoint&, const EdgePoint&) = default;
};

inline std::set<EdgePoint> EdgePoints(const QuantizedMesh& m, const std::vector<uint32_t>& edge,
                                      bool along_v) {
  std::set<EdgePoint> out;
  for (uint32_t i : edge) out.insert({along_v ? m.v[i] : m.u[i], m.height[i]});
  return out;
}

// Expects every east and north neighbour pair in `tiles` to agree along its shared edge; returns
// how many pairs were compared.
inline int ExpectSeamsMatch(const std::map<TileKey, QuantizedMesh>& tiles) {
  int pairs = 0;
  for (const auto& [key, mesh] : tiles) {
    if (auto east = tiles.find({key.level, key.x + 1, key.y}); east != tiles.end()) {
      EXPECT_EQ(EdgePoints(mesh, mesh.east, true),
                EdgePoints(east->second, east->second.west, true))
          << key.ToString() << " and its east neighbour";
      ++pairs;
    }
    if (auto north = tiles.find({key.level, key.x, key.y + 1}); north != tiles.end()) {
      EXPECT_EQ(EdgePoints(mesh, mesh.north, false),
                EdgePoints(north->second, north->second.south, false))
          << key.ToString() << " and its north neighbour";
      ++pairs;
    }
  }
  return pairs;
}

}  // namespace tinbase::testing
