// SegmentIndex finds points exactly on any of many segments, and only those, with the segments
// spread over its bucket grid.
#include "core/geometry/segment_index.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

namespace tinbase {
namespace {

TEST(SegmentIndex, EmptyHoldsNothing) {
  SegmentIndex index;
  EXPECT_FALSE(index.OnAny({0, 0}));
  index.Build({});
  EXPECT_FALSE(index.OnAny({0, 0}));
}

TEST(SegmentIndex, PointsOnAndBesideAPolyline) {
  // A closed ring of 400 unit segments around a 100 x 100 square.
  std::vector<std::pair<Point2, Point2>> segments;
  for (int k = 0; k < 100; ++k) {
    const double a = k, b = k + 1;
    segments.push_back({{a, 0}, {b, 0}});
    segments.push_back({{100, a}, {100, b}});
    segments.push_back({{b, 100}, {a, 100}});
    segments.push_back({{0, b}, {0, a}});
  }
  SegmentIndex index;
  index.Build(segments);
  EXPECT_TRUE(index.OnAny({0.5, 0}));
  EXPECT_TRUE(index.OnAny({100, 37.25}));
  EXPECT_TRUE(index.OnAny({0, 0}));     // a corner
  EXPECT_TRUE(index.OnAny({63, 100}));  // a joint of two segments
  EXPECT_FALSE(index.OnAny({50, 50}));  // inside the ring
  EXPECT_FALSE(index.OnAny({101, 0}));  // outside every segment's box
  EXPECT_FALSE(index.OnAny({37.5, std::nextafter(0.0, 1.0)}));
  EXPECT_FALSE(index.OnAny({std::nextafter(100.0, 200.0), 12}));
}

TEST(SegmentIndex, AgreesWithABruteForceScanOnRandomSegments) {
  std::mt19937_64 random(20261127);
  std::uniform_real_distribution<double> coordinate(0, 1000);
  std::vector<std::pair<Point2, Point2>> segments;
  for (int k = 0; k < 500; ++k)
    segments.push_back(
        {{coordinate(random), coordinate(random)}, {coordinate(random), coordinate(random)}});
  SegmentIndex index;
  index.Build(segments);
  std::uniform_real_distribution<double> along(0, 1);
  int on = 0;
  for (int k = 0; k < 2000; ++k) {
    // Half the queries are segment ends (exactly on), half random points (almost never on).
    const auto& [a, b] = segments[k % segments.size()];
    const Point2 p =
        k % 2 == 0 ? (k % 4 == 0 ? a : b) : Point2{coordinate(random), coordinate(random)};
    bool brute = false;
    for (const auto& [s, t] : segments)
      brute |= std::min(s.x, t.x) <= p.x && p.x <= std::max(s.x, t.x) &&
               std::min(s.y, t.y) <= p.y && p.y <= std::max(s.y, t.y) && Orientation(s, t, p) == 0;
    EXPECT_EQ(index.OnAny(p), brute) << p.x << ", " << p.y;
    on += brute;
  }
  EXPECT_GE(on, 1000);
  (void)along;
}

}  // namespace
}  // namespace tinbase
