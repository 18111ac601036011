// TriangleBatch: part of a Tin's triangles, handed over while the rest is still being computed.
//
// A bulk Delaunay build (Cdt::InsertVerticesInBands) hands its triangles over in batches as they
// become final, so the store can write rows while the triangulation runs. Batches continue one
// index sequence: concatenated, they are Tin::triangles. A neighbour that is not final when its
// triangle is handed over is linked later, by a Link of a later batch. Plain data.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/tin/tin.h"

namespace tinbase {

struct TriangleBatch {
  // A neighbour link of a triangle of an earlier batch, unknown when that batch was handed over.
  struct Link {
    uint32_t triangle = 0;  // index of the triangle
    int slot = 0;           // its n[slot]
    int32_t neighbour = 0;  // the index to put there
  };

  size_t first = 0;  // index of triangles[0]; the next batch's first is first + triangles.size()
  // n[i] is kNoNeighbour across the convex hull and where the neighbour is not final yet.
  std::vector<TinTriangle> triangles;
  std::vector<int64_t> keys;  // the TriangleOrder key of each triangle (ascending)
  std::vector<Link> links;
};

// The key batches are sorted by (a store writes rows in its index's order).
using TriangleOrder = std::function<int64_t(const TinTriangle&)>;
using TriangleSink = std::function<void(TriangleBatch)>;

}  // namespace tinbase
