// A generated Tin for tests: a regular grid of nx x ny square cells, each cut into two
// counter-clockwise triangles, with neighbours linked. Header-only; plain function.
#pragma once

#include <cassert>
#include <cstdint>
#include <functional>

#include "core/tin/tin.h"

namespace tinbase::testing {

// Vertices at (x0 + i * cell, y0 + j * cell) for i in [0, nx], j in [0, ny], index j*(nx+1)+i;
// z = height(x, y). Cells alternate their diagonal so the mesh has no preferred direction.
inline Tin MakeGridTin(int nx, int ny, double cell, double x0 = 0, double y0 = 0,
                       const std::function<double(double, double)>& height = {}) {
  Tin tin;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const double x = x0 + i * cell;
      const double y = y0 + j * cell;
      tin.vertices.push_back({x, y, height ? height(x, y) : 0.0, VertexKind::kDem});
    }
  }
  const auto id = [nx](int i, int j) { return static_cast<uint32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      TinTriangle t1, t2;
      if ((i + j) % 2 == 0) {
        t1.v = {a, b, c};
        t2.v = {a, c, d};
      } else {
        t1.v = {a, b, d};
        t2.v = {b, c, d};
      }
      tin.triangles.push_back(t1);
      tin.triangles.push_back(t2);
    }
  }
  [[maybe_unused]] const bool linked = LinkNeighbours(tin);
  assert(linked);
  return tin;
}

}  // namespace tinbase::testing
