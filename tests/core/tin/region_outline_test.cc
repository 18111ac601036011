// DirectedOutline and ClassifyInside on a Delaunay triangulation of a grid: the triangles inside
// a region's directed outline are found from the outline alone, also when the outline is not
// convex, and reversing the outline gives the complement.
#include "core/tin/region_outline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "core/geometry/cdt.h"

namespace tinbase {
namespace {

TEST(DirectedOutline, KnowsEachEdgeInItsDirectionOnly) {
  const DirectedOutline outline(5, {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {3, 0}});
  EXPECT_TRUE(outline.Has(0, 1));
  EXPECT_TRUE(outline.Has(3, 4));
  EXPECT_TRUE(outline.Has(3, 0));
  EXPECT_FALSE(outline.Has(1, 0));
  EXPECT_FALSE(outline.Has(4, 3));
  EXPECT_FALSE(outline.Has(2, 1));
  EXPECT_FALSE(outline.Has(7, 0));  // beyond the vertices
}

// A 7 x 7 grid of points, triangulated; the region is the triangles whose centroid lies in an
// L-shaped set of unit cells. Its outline is every edge of a region triangle whose other side is
// not in the region, directed as the region triangle has it.
TEST(ClassifyInside, FindsAnLShapedRegionFromItsOutline) {
  std::vector<TinVertex> points;
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 7; ++x) points.push_back({x + 0.01 * ((x * 7 + y) % 3), y + 0.0, 0});
  Cdt cdt;
  cdt.InsertVertices(points);
  const Tin tin = cdt.ToTin([](double, double) { return 0.0; });
  const auto in_l = [&](const TinTriangle& t) {
    double cx = 0, cy = 0;
    for (uint32_t v : t.v) cx += tin.vertices[v].x / 3, cy += tin.vertices[v].y / 3;
    return (cx > 1 && cx < 5 && cy > 1 && cy < 3) || (cx > 1 && cx < 3 && cy > 1 && cy < 5);
  };
  std::vector<uint8_t> expected;
  std::vector<std::pair<uint32_t, uint32_t>> edges, reversed;
  for (const TinTriangle& t : tin.triangles) {
    expected.push_back(in_l(t) ? 1 : 0);
    if (!in_l(t)) continue;
    for (int i = 0; i < 3; ++i) {
      const int32_t n = t.n[i];
      if (n != kNoNeighbour && in_l(tin.triangles[n])) continue;
      const uint32_t a = t.v[(i + 1) % 3], b = t.v[(i + 2) % 3];
      edges.push_back({a, b});
      reversed.push_back({b, a});
    }
  }
  const size_t inside = std::count(expected.begin(), expected.end(), 1);
  ASSERT_GT(inside, 8u);
  ASSERT_LT(inside, tin.triangles.size() / 2);
  EXPECT_EQ(ClassifyInside(tin, DirectedOutline(tin.vertices.size(), edges)), expected);
  std::vector<uint8_t> complement = expected;
  for (uint8_t& c : complement) c = 1 - c;
  EXPECT_EQ(ClassifyInside(tin, DirectedOutline(tin.vertices.size(), reversed)), complement);
}

TEST(ClassifyInside, NoOutlineMeansNothingInside) {
  std::vector<TinVertex> points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1.1, 0}};
  Cdt cdt;
  cdt.InsertVertices(points);
  const Tin tin = cdt.ToTin([](double, double) { return 0.0; });
  const std::vector<uint8_t> inside = ClassifyInside(tin, DirectedOutline(4, {}));
  EXPECT_EQ(inside, std::vector<uint8_t>(tin.triangles.size(), 0));
}

}  // namespace
}  // namespace tinbase
