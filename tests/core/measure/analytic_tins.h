// TINs of analytic surfaces for the measure tests: a regular grid over a rectangle (each cell
// split by one diagonal) and a Delaunay triangulation of concentric rings over a disc, with z
// from a given function, so that areas, volumes, slopes and contours have known answers.
// Header-only.
#pragma once

#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "core/geometry/cdt.h"
#include "core/tin/tin.h"

namespace tinbase::testing {

using HeightFn = std::function<double(double x, double y)>;

// nx by ny cells over [x0, x1] x [y0, y1], each cell split along alternating diagonals; vertices
// row by row. Neighbours linked.
inline Tin GridTin(int nx, int ny, double x0, double y0, double x1, double y1, const HeightFn& z) {
  Tin tin;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const double x = i == nx ? x1 : x0 + (x1 - x0) * i / nx;
      const double y = j == ny ? y1 : y0 + (y1 - y0) * j / ny;
      tin.vertices.push_back({x, y, z(x, y), VertexKind::kDem});
    }
  }
  const auto at = [&](int i, int j) { return static_cast<uint32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      TinTriangle t1, t2;
      if ((i + j) % 2 == 0) {
        t1.v = {a, b, c}, t2.v = {a, c, d};
      } else {
        t1.v = {a, b, d}, t2.v = {b, c, d};
      }
      tin.triangles.push_back(t1);
      tin.triangles.push_back(t2);
    }
  }
  LinkNeighbours(tin);
  return tin;
}

// A disc of radius r around the origin: the centre and `rings` rings at radius r k / rings with
// 6 k points each, Delaunay-triangulated. The hull is a polygon inscribed in the circle.
inline Tin DiscTin(int rings, double r, const HeightFn& z) {
  std::vector<TinVertex> points = {{0, 0, z(0, 0), VertexKind::kDem}};
  for (int k = 1; k <= rings; ++k) {
    const double radius = r * k / rings;
    for (int m = 0; m < 6 * k; ++m) {
      const double a = 2 * std::numbers::pi * m / (6 * k);
      const double x = radius * std::cos(a), y = radius * std::sin(a);
      points.push_back({x, y, z(x, y), VertexKind::kDem});
    }
  }
  Cdt cdt;
  cdt.InsertVertices(points);
  return cdt.ToTin();
}

inline double Paraboloid(double x, double y) { return x * x + y * y; }

}  // namespace tinbase::testing
