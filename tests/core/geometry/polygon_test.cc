// Polygon validation and point location: hand-made cases, and properties checked against
// OGR/GEOS on random small rings (RapidCheck prints the seed of any failure).
#include "core/geometry/polygon.h"

#include <gtest/gtest.h>
#include <ogr_geometry.h>
#include <rapidcheck/gtest.h>

#include <memory>

#include "core/geometry/polygon_locator.h"
#include "core/vector/gdal_session.h"

namespace tinbase {

// How RapidCheck shows a counterexample's points (found by argument-dependent lookup).
inline void showValue(const Point2& p, std::ostream& os) { os << FormatPoint(p); }

namespace {

Ring Closed(Ring ring) {
  ring.push_back(ring.front());
  return ring;
}

OGRPolygon ToOgr(const std::vector<Ring>& closed_rings) {
  OGRPolygon polygon;
  for (const Ring& ring : closed_rings) {
    OGRLinearRing lr;
    for (const Point2& p : ring) lr.addPoint(p.x, p.y);
    polygon.addRing(&lr);
  }
  return polygon;
}

TEST(MakeValidPolygon, OrientsRingsAndDropsRepeatsAndTheClosingVertex) {
  // A clockwise shell with a repeated vertex, and a counter-clockwise hole.
  auto p = MakeValidPolygon(
      {Closed({{0, 0}, {0, 10}, {0, 10}, {10, 10}, {10, 0}}), Closed({{2, 2}, {4, 2}, {4, 4}})});
  ASSERT_TRUE(p.ok()) << p.status().ToString();
  EXPECT_EQ(p->shell.size(), 4u);
  EXPECT_GT(SignedDoubleArea(p->shell), 0);
  ASSERT_EQ(p->holes.size(), 1u);
  EXPECT_EQ(p->holes[0].size(), 3u);
  EXPECT_LT(SignedDoubleArea(p->holes[0]), 0);
  EXPECT_EQ(SignedDoubleArea(p->shell), 200);
}

TEST(MakeValidPolygon, AllowsRingsTouchingAtAPoint) {
  // A hole touching the shell at one vertex, and two holes touching each other.
  auto p = MakeValidPolygon({Closed({{0, 0}, {10, 0}, {10, 10}, {0, 10}}),
                             Closed({{0, 5}, {3, 4}, {3, 6}}), Closed({{3, 6}, {6, 6}, {6, 8}})});
  EXPECT_TRUE(p.ok()) << p.status().ToString();
}

TEST(MakeValidPolygon, RejectsSharedEdgesAndEmptyInput) {
  auto shared = MakeValidPolygon(
      {Closed({{0, 0}, {10, 0}, {10, 10}, {0, 10}}), Closed({{0, 2}, {3, 3}, {0, 6}})});
  ASSERT_FALSE(shared.ok());
  EXPECT_EQ(shared.status().message(),
            "ring 0, vertex 3: shares an edge with ring 1 at (0, 2) (edges 3-0 and ring 1 2-0)");
  // The hole touches the shell at two points, cutting off the corner near (0, 0).
  auto cut = MakeValidPolygon(
      {Closed({{0, 0}, {10, 0}, {10, 10}, {0, 10}}), Closed({{2, 0}, {3, 3}, {0, 2}})});
  ASSERT_FALSE(cut.ok());
  EXPECT_EQ(cut.status().message(),
            "ring 1: touches at (2, 0) rings it already touches elsewhere, cutting the polygon's "
            "interior apart");
  auto none = MakeValidPolygon({});
  ASSERT_FALSE(none.ok());
  auto empty_ring = MakeValidPolygon({{}});
  ASSERT_FALSE(empty_ring.ok());
  EXPECT_EQ(empty_ring.status().message(), "ring 0: ring is not closed");
}

TEST(LocateInRing, TellsInsideBoundaryAndOutside) {
  const Ring ring = {{0, 0}, {4, 0}, {4, 4}, {2, 2}, {0, 4}};  // concave
  EXPECT_EQ(LocateInRing(ring, {1, 1}), PointInPolygon::kInside);
  EXPECT_EQ(LocateInRing(ring, {2, 3}), PointInPolygon::kOutside);   // in the notch
  EXPECT_EQ(LocateInRing(ring, {2, 2}), PointInPolygon::kBoundary);  // vertex
  EXPECT_EQ(LocateInRing(ring, {3, 3}), PointInPolygon::kBoundary);  // on an edge
  EXPECT_EQ(LocateInRing(ring, {2, 0}), PointInPolygon::kBoundary);  // horizontal edge
  EXPECT_EQ(LocateInRing(ring, {5, 0}), PointInPolygon::kOutside);   // on the edge's line, beyond
  EXPECT_EQ(LocateInRing(ring, {-1, 2}),
            PointInPolygon::kOutside);  // ray through the vertex (2, 2)
  EXPECT_EQ(LocateInRing(ring, {1, 2}), PointInPolygon::kInside);
}

// Random rings on a small integer grid hit every degenerate case: repeated, collinear and
// shared vertices, touching and overlapping edges.
rc::Gen<Ring> SmallRing() {
  return rc::gen::container<Ring>(
      *rc::gen::inRange<size_t>(3, 9),
      rc::gen::construct<Point2>(
          rc::gen::map(rc::gen::inRange(0, 6), [](int v) { return 1.0 * v; }),
          rc::gen::map(rc::gen::inRange(0, 6), [](int v) { return 1.0 * v; })));
}

RC_GTEST_PROP(MakeValidPolygon, AcceptsAShellExactlyWhenGeosCallsItValid, ()) {
  const Ring ring = *SmallRing();
  const Ring closed = Closed(ring);
  QuietGdalErrors quiet;  // GEOS explains each invalid ring on stderr otherwise
  auto ours = MakeValidPolygon({closed});
  const OGRPolygon theirs = ToOgr({closed});
  RC_CLASSIFY(ours.ok(), "valid");
  RC_ASSERT(ours.ok() == theirs.IsValid());
  if (ours.ok()) {
    RC_ASSERT(SignedDoubleArea(ours->shell) > 0);
    RC_ASSERT(std::abs(SignedDoubleArea(ours->shell) / 2 - theirs.get_Area()) < 1e-9);
  }
}

RC_GTEST_PROP(PolygonLocator, AgreesWithTheLinearScanAndGeos, ()) {
  const Ring ring = *SmallRing();
  auto polygon = MakeValidPolygon({Closed(ring)});
  RC_PRE(polygon.ok());
  QuietGdalErrors quiet;
  const PolygonLocator locator({*polygon});
  const OGRPolygon ogr = ToOgr({Closed(polygon->shell)});
  // Half-integer points land on vertices, edges and in between.
  for (int i = -1; i <= 13; ++i) {
    for (int j = -1; j <= 13; ++j) {
      const Point2 p{i / 2.0, j / 2.0};
      const PointInPolygon got = locator.Locate(p);
      RC_ASSERT(got == LocateInRing(polygon->shell, p));
      OGRPoint point(p.x, p.y);
      RC_ASSERT((got == PointInPolygon::kInside) == ogr.Contains(&point));
      RC_ASSERT((got == PointInPolygon::kBoundary) ==
                (point.Intersects(&ogr) && !ogr.Contains(&point)));
    }
  }
}

TEST(PolygonLocator, IsTheUnionOfOverlappingPolygonsWithHoles) {
  const Polygon a{{{0, 0}, {10, 0}, {10, 10}, {0, 10}}, {{{2, 2}, {2, 8}, {8, 8}, {8, 2}}}};
  const Polygon b{{{5, 5}, {15, 5}, {15, 15}, {5, 15}}, {}};
  const PolygonLocator locator({a, b});
  EXPECT_EQ(locator.Locate({1, 1}), PointInPolygon::kInside);
  EXPECT_EQ(locator.Locate({3, 3}), PointInPolygon::kOutside);   // a's hole, outside b
  EXPECT_EQ(locator.Locate({6, 6}), PointInPolygon::kInside);    // a's hole, inside b
  EXPECT_EQ(locator.Locate({10, 7}), PointInPolygon::kInside);   // a's edge, inside b
  EXPECT_EQ(locator.Locate({2, 3}), PointInPolygon::kBoundary);  // a's hole edge, outside b
  EXPECT_EQ(locator.Locate({12, 12}), PointInPolygon::kInside);
  EXPECT_EQ(locator.Locate({12, 2}), PointInPolygon::kOutside);
  EXPECT_EQ(locator.Locate({15, 20}), PointInPolygon::kOutside);
  EXPECT_EQ(PolygonLocator({}).Locate({0, 0}), PointInPolygon::kOutside);
}

}  // namespace
}  // namespace tinbase

namespace tinbase {
namespace {

RC_GTEST_PROP(MakeValidPolygon, AcceptsHolesExactlyWhenGeosCallsThemValid, ()) {
  // Half the time a square shell on the grid's border, so that many holes fit inside it.
  const bool square = *rc::gen::arbitrary<bool>();
  const Ring shell = Closed(square ? Ring{{0, 0}, {5, 0}, {5, 5}, {0, 5}} : *SmallRing());
  const Ring hole = Closed(*SmallRing());
  QuietGdalErrors quiet;
  auto ours = MakeValidPolygon({shell, hole});
  const OGRPolygon theirs = ToOgr({shell, hole});
  RC_CLASSIFY(ours.ok(), "valid");
  RC_ASSERT(ours.ok() == theirs.IsValid());
}

}  // namespace
}  // namespace tinbase
