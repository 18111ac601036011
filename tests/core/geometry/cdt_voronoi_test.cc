// Cdt::VoronoiCells: cell areas and neighbours, checked against a grid's known cells and against
// a brute-force Voronoi cell (a box clipped by the bisector of every other point).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/geometry/cdt.h"

namespace tinbase {
namespace {

TEST(CdtVoronoi, RegularGridCellsAreSquares) {
  std::vector<TinVertex> grid;
  const int n = 12;
  const double s = 2.5;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) grid.push_back({1000 + s * i, 5000 + s * j, 0});
  }
  Cdt cdt;
  cdt.InsertVertices(grid);
  const std::vector<VoronoiCell> cells = cdt.VoronoiCells();
  ASSERT_EQ(cells.size(), grid.size());
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const VoronoiCell& c = cells[static_cast<size_t>(i) * n + j];
      const bool border = i == 0 || j == 0 || i == n - 1 || j == n - 1;
      EXPECT_EQ(c.bounded, !border) << i << "," << j;
      if (!border) {
        EXPECT_NEAR(c.area, s * s, 1e-9) << i << "," << j;
      }
    }
  }
}

// The Voronoi cell of points[k] by brute force: clip a big square by the half-plane nearer to
// points[k] than to each other point (Sutherland-Hodgman), then take its area.
double BruteForceCellArea(const std::vector<TinVertex>& points, size_t k) {
  using P = std::pair<double, double>;
  const double px = points[k].x, py = points[k].y;
  std::vector<P> poly = {{-1e4, -1e4}, {1e4, -1e4}, {1e4, 1e4}, {-1e4, 1e4}};
  for (size_t j = 0; j < points.size(); ++j) {
    if (j == k) continue;
    // Keep q with (q - m) . (o - p) <= 0, m the midpoint, o the other point (relative to p).
    const double ox = points[j].x - px, oy = points[j].y - py;
    const double mx = ox / 2, my = oy / 2;
    const auto side = [&](const P& q) { return (q.first - mx) * ox + (q.second - my) * oy; };
    std::vector<P> out;
    for (size_t i = 0; i < poly.size(); ++i) {
      const P& a = poly[i];
      const P& b = poly[(i + 1) % poly.size()];
      const double sa = side(a), sb = side(b);
      if (sa <= 0) out.push_back(a);
      if ((sa < 0 && sb > 0) || (sa > 0 && sb < 0)) {
        const double t = sa / (sa - sb);
        out.push_back({a.first + t * (b.first - a.first), a.second + t * (b.second - a.second)});
      }
    }
    poly = std::move(out);
  }
  double twice = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const P& a = poly[i];
    const P& b = poly[(i + 1) % poly.size()];
    twice += a.first * b.second - b.first * a.second;
  }
  return std::abs(twice) / 2;
}

TEST(CdtVoronoi, RandomCellsMatchBruteForce) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coord(0, 100);
  std::vector<TinVertex> points;
  for (int i = 0; i < 300; ++i) points.push_back({636000 + coord(rng), 849000 + coord(rng), 0});
  Cdt cdt;
  cdt.InsertVertices(points);
  const std::vector<VoronoiCell> cells = cdt.VoronoiCells();
  // Relative to the first point, so the brute force works in small numbers.
  std::vector<TinVertex> local = points;
  for (TinVertex& p : local) {
    p.x -= 636000;
    p.y -= 849000;
  }
  int bounded = 0;
  for (size_t k = 0; k < points.size(); ++k) {
    // Neighbour lists are symmetric.
    for (uint32_t n : cells[k].neighbours) {
      const auto& back = cells[n].neighbours;
      EXPECT_NE(std::find(back.begin(), back.end(), k), back.end()) << k << " - " << n;
    }
    if (!cells[k].bounded) continue;
    ++bounded;
    EXPECT_NEAR(cells[k].area, BruteForceCellArea(local, k), 1e-6 * cells[k].area) << k;
  }
  EXPECT_GT(bounded, 250);
}

TEST(CdtVoronoi, CollinearPointsHaveNoBoundedCell) {
  std::vector<TinVertex> line;
  for (int i = 0; i < 5; ++i) line.push_back({double(i), double(i), 0});
  Cdt cdt;
  cdt.InsertVertices(line);
  const auto cells = cdt.VoronoiCells();
  ASSERT_EQ(cells.size(), 5u);
  for (const VoronoiCell& c : cells) EXPECT_FALSE(c.bounded);
  EXPECT_EQ(cells[2].neighbours.size(), 2u);
  EXPECT_EQ(cells[0].neighbours.size(), 1u);
}

}  // namespace
}  // namespace tinbase
