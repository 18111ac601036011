// Feature painting on generated grid TINs: squares and holed squares checked against the grid's
// own arithmetic, arbitrary shapes and the Hamersley geology checked against OGR/GEOS, and the
// size the brief asks for (1e5 triangles against rings of 6000 vertices) timed.
#include "core/tin/feature_paint.h"

#include <gtest/gtest.h>
#include <ogr_api.h>
#include <ogr_geometry.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <random>

#include "core/vector/polygon_source.h"
#include "tests/support/grid_tin.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::MakeGridTin;

Ring Box(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

PaintedFeature Feature(FeatureMode mode, std::vector<Polygon> polygons, int32_t tag = kNoTag,
                       double level = 0) {
  PaintedFeature f;
  f.mode = mode;
  f.inside = std::make_shared<const PolygonLocator>(polygons);
  f.tag = tag;
  f.level = level;
  return f;
}

// The centroid of triangle t, computed here independently of the painter.
Point2 CentroidOf(const Tin& tin, size_t t) {
  Point2 c;
  for (uint32_t v : tin.triangles[t].v) {
    c.x += tin.vertices[v].x / 3;
    c.y += tin.vertices[v].y / 3;
  }
  return c;
}

bool InBox(const Point2& p, double x0, double y0, double x1, double y1) {
  return x0 < p.x && p.x < x1 && y0 < p.y && p.y < y1;
}

size_t Count(const std::vector<uint8_t>& v) { return std::count(v.begin(), v.end(), 1); }

// A breakline is a feature mode but paints nothing (its parsing: feature_mode_test.cc).
TEST(FeaturePaint, BreaklinePaintsNothing) {
  Tin tin = MakeGridTin(10, 10, 1.0);
  tin.tags = {"unit"};
  const Paint paint =
      ComputePaint(tin, {Feature(FeatureMode::kBreakline, {{Box(0, 0, 10, 10), {}}}, 0, 5)});
  EXPECT_EQ(Count(paint.visible), tin.triangles.size());
  for (int32_t tag : paint.tag) EXPECT_EQ(tag, kNoTag);
  EXPECT_TRUE(paint.levels.empty());
}

TEST(FeaturePaint, NoFeaturesLeaveEverythingVisibleAndUntagged) {
  const Tin tin = MakeGridTin(10, 10, 1.0);
  const Paint paint = ComputePaint(tin, {});
  EXPECT_EQ(Count(paint.visible), tin.triangles.size());
  for (int32_t tag : paint.tag) EXPECT_EQ(tag, kNoTag);
  EXPECT_TRUE(paint.levels.empty());
}

TEST(FeaturePaint, ClipKeepsTheUnionOfClipPolygons) {
  const Tin tin = MakeGridTin(40, 40, 1.0);
  const Paint one = ComputePaint(tin, {Feature(FeatureMode::kClip, {{Box(10, 10, 30, 30), {}}})});
  EXPECT_EQ(Count(one.visible), 20u * 20u * 2u);
  // Two clip features overlapping: the union, not the intersection.
  const Paint two = ComputePaint(tin, {Feature(FeatureMode::kClip, {{Box(0, 0, 10, 10), {}}}),
                                       Feature(FeatureMode::kClip, {{Box(5, 5, 20, 20), {}}})});
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const Point2 c = CentroidOf(tin, t);
    EXPECT_EQ(two.visible[t] != 0, InBox(c, 0, 0, 10, 10) || InBox(c, 5, 5, 20, 20)) << t;
  }
  EXPECT_EQ(Count(two.visible), (100u + 225u - 25u) * 2u);
}

TEST(FeaturePaint, EraseHidesTheInsideButNotTheHole) {
  const Tin tin = MakeGridTin(40, 40, 1.0);
  const Polygon holed{Box(5, 5, 35, 35), {Box(15, 15, 25, 25)}};
  const Paint paint = ComputePaint(tin, {Feature(FeatureMode::kErase, {holed})});
  EXPECT_EQ(tin.triangles.size() - Count(paint.visible), (30u * 30u - 10u * 10u) * 2u);
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const Point2 c = CentroidOf(tin, t);
    const bool erased = InBox(c, 5, 5, 35, 35) && !InBox(c, 15, 15, 25, 25);
    EXPECT_EQ(paint.visible[t] == 0, erased) << t;
  }
  // Clip and erase together: only what both leave.
  const Paint both = ComputePaint(tin, {Feature(FeatureMode::kErase, {holed}),
                                        Feature(FeatureMode::kClip, {{Box(0, 0, 20, 40), {}}})});
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const Point2 c = CentroidOf(tin, t);
    const bool shown =
        InBox(c, 0, 0, 20, 40) && !(InBox(c, 5, 5, 35, 35) && !InBox(c, 15, 15, 25, 25));
    EXPECT_EQ(both.visible[t] != 0, shown) << t;
  }
}

TEST(FeaturePaint, LaterFillsWinWhereTheyOverlap) {
  Tin tin = MakeGridTin(40, 40, 1.0);
  tin.tags = {"sand", "clay", "rock"};
  const std::vector<PaintedFeature> features = {
      Feature(FeatureMode::kFill, {{Box(0, 0, 20, 40), {}}}, 0),
      Feature(FeatureMode::kFill, {{Box(10, 0, 30, 40), {Box(12, 12, 14, 14)}}}, 1),
      Feature(FeatureMode::kFill, {{Box(25, 25, 40, 40), {}}, {Box(0, 35, 5, 40), {}}}, 2)};
  const Paint paint = ComputePaint(tin, features);
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const Point2 c = CentroidOf(tin, t);
    int32_t want = kNoTag;
    if (InBox(c, 0, 0, 20, 40)) want = 0;
    if (InBox(c, 10, 0, 30, 40) && !InBox(c, 12, 12, 14, 14)) want = 1;
    if (InBox(c, 25, 25, 40, 40) || InBox(c, 0, 35, 5, 40)) want = 2;
    EXPECT_EQ(paint.tag[t], want) << t;
  }
  EXPECT_EQ(Count(paint.visible), tin.triangles.size());  // filling never hides
  ApplyPaint(paint, tin, false);
  for (size_t t = 0; t < tin.triangles.size(); ++t) EXPECT_EQ(tin.triangles[t].tag, paint.tag[t]);
}

TEST(FeaturePaint, ReplaceTagsAndLevelsVerticesInsideAndOnTheRing) {
  Tin tin = MakeGridTin(30, 30, 2.0, 100, 200, [](double x, double y) { return x + y; });
  tin.tags = {"lake", "quarry"};
  const std::vector<PaintedFeature> features = {
      Feature(FeatureMode::kReplace, {{Box(110, 210, 130, 230), {}}}, 0, 55.5),
      Feature(FeatureMode::kReplace, {{Box(126, 226, 140, 240), {}}}, 1, 77.25)};
  const Paint paint = ComputePaint(tin, features);
  size_t second = 0;
  for (const VertexLevel& level : paint.levels) {
    const TinVertex& v = tin.vertices[level.vertex];
    const bool in_second = 126 <= v.x && v.x <= 140 && 226 <= v.y && v.y <= 240;
    EXPECT_TRUE(in_second || (110 <= v.x && v.x <= 130 && 210 <= v.y && v.y <= 230));
    EXPECT_EQ(level.z, in_second ? 77.25 : 55.5);
    second += in_second;
  }
  // 11 x 11 grid vertices in/on the first square, 8 x 8 in/on the second, 3 x 3 shared.
  EXPECT_EQ(paint.levels.size(), 121u + 64u - 9u);
  EXPECT_EQ(second, 64u);
  for (size_t i = 1; i < paint.levels.size(); ++i)
    EXPECT_LT(paint.levels[i - 1].vertex, paint.levels[i].vertex);
  size_t tagged = 0;
  for (int32_t tag : paint.tag) tagged += tag != kNoTag;
  EXPECT_EQ(tagged, (100u + 49u - 4u) * 2u);

  const Tin before = tin;
  ApplyPaint(paint, tin, true);
  for (size_t v = 0; v < tin.vertices.size(); ++v) {
    const TinVertex& p = tin.vertices[v];
    const bool first = 110 <= p.x && p.x <= 130 && 210 <= p.y && p.y <= 230;
    const bool last = 126 <= p.x && p.x <= 140 && 226 <= p.y && p.y <= 240;
    EXPECT_EQ(p.z, last ? 77.25 : first ? 55.5 : before.vertices[v].z) << v;
  }
}

// OGR/GEOS as the independent judge of "centroid inside".
std::unique_ptr<OGRGeometry> ToOgr(const std::vector<Polygon>& polygons) {
  auto multi = std::make_unique<OGRMultiPolygon>();
  for (const Polygon& p : polygons) {
    OGRPolygon polygon;
    for (size_t r = 0; r <= p.holes.size(); ++r) {
      const Ring& ring = r == 0 ? p.shell : p.holes[r - 1];
      OGRLinearRing lr;
      for (const Point2& q : ring) lr.addPoint(q.x, q.y);
      lr.addPoint(ring[0].x, ring[0].y);
      polygon.addRing(&lr);
    }
    multi->addGeometry(&polygon);
  }
  return multi;
}

// `polygons[k]` are the polygons features[k] was made of.
void ExpectMatchesOgr(const Tin& tin, const std::vector<PaintedFeature>& features,
                      const std::vector<std::vector<Polygon>>& polygons, const Paint& paint,
                      size_t step) {
  std::vector<std::unique_ptr<OGRGeometry>> shapes;
  std::vector<OGRPreparedGeometryUniquePtr> prepared;
  for (const std::vector<Polygon>& p : polygons) {
    shapes.push_back(ToOgr(p));
    prepared.emplace_back(OGRCreatePreparedGeometry(OGRGeometry::ToHandle(shapes.back().get())));
    ASSERT_TRUE(prepared.back()) << "GDAL built without GEOS";
  }
  size_t checked = 0;
  for (size_t t = 0; t < tin.triangles.size(); t += step) {
    const Point2 c = CentroidOf(tin, t);
    OGRPoint point(c.x, c.y);
    int32_t want = kNoTag;
    for (size_t k = 0; k < features.size(); ++k)
      if (OGRPreparedGeometryContains(prepared[k].get(), OGRGeometry::ToHandle(&point)))
        want = features[k].tag;
    EXPECT_EQ(paint.tag[t], want) << "triangle " << t << " centroid " << FormatPoint(c);
    ++checked;
  }
  EXPECT_GT(checked, 100u);
}

// A star-shaped ring of `n` vertices with a jagged radius: long and short edges, many
// concavities, every vertex off the grid.
Ring Star(double cx, double cy, double r, int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(0.55, 1.0);
  Ring ring;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * i / n;
    const double radius = r * jitter(rng);
    ring.push_back({cx + radius * std::cos(a), cy + radius * std::sin(a)});
  }
  return ring;
}

TEST(FeaturePaint, LargeRingsOverManyTrianglesAgreeWithGeos) {
  // 224 x 224 cells: 100352 triangles; a 6000-vertex ring with a 600-vertex hole.
  const Tin tin = MakeGridTin(224, 224, 1.0);
  Ring hole = Star(112, 112, 30, 600, 7);
  std::reverse(hole.begin(), hole.end());
  auto valid = MakeValidPolygon([&] {
    std::vector<Ring> rings = {Star(112, 112, 110, 6000, 3), hole};
    for (Ring& r : rings) r.push_back(r.front());
    return rings;
  }());
  ASSERT_TRUE(valid.ok()) << valid.status().ToString();
  const std::vector<std::vector<Polygon>> polygons = {{*valid}, {{Star(60, 160, 40, 500, 11), {}}}};
  const std::vector<PaintedFeature> features = {Feature(FeatureMode::kFill, polygons[0], 0),
                                                Feature(FeatureMode::kFill, polygons[1], 1)};
  const Paint paint = ComputePaint(tin, features);
  ExpectMatchesOgr(tin, features, polygons, paint, 7);
}

TEST(FeaturePaint, HamersleyGeologyFillAgreesWithGeos) {
  auto geology = ReadPolygonFeatures(testing::DataPath("geology/hamersley/geology.geojson"), {});
  ASSERT_TRUE(geology.ok()) << geology.status().ToString();
  // A grid over the map's extent (about 47 x 48 km) at 150 m: ~1e5 triangles.
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const PolygonFeature& f : *geology) {
    for (const Point2& p : f.polygons[0].shell) {
      x0 = std::min(x0, p.x), y0 = std::min(y0, p.y);
      x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
    }
  }
  const double cell = 150;
  Tin tin = MakeGridTin(static_cast<int>((x1 - x0) / cell) + 1,
                        static_cast<int>((y1 - y0) / cell) + 1, cell, x0, y0);
  std::vector<PaintedFeature> features;
  std::vector<std::vector<Polygon>> polygons;
  for (const PolygonFeature& f : *geology) {
    tin.tags.push_back(f.attributes["unitname"].get<std::string>());
    features.push_back(
        Feature(FeatureMode::kFill, f.polygons, static_cast<int32_t>(tin.tags.size() - 1)));
    polygons.push_back(f.polygons);
  }
  const Paint paint = ComputePaint(tin, features);
  size_t tagged = 0;
  for (int32_t tag : paint.tag) tagged += tag != kNoTag;
  EXPECT_GT(tagged, tin.triangles.size() / 2);  // the map covers most of its extent
  ExpectMatchesOgr(tin, features, polygons, paint, 5);
}

}  // namespace
}  // namespace tinbase
