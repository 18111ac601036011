// Constraint polylines inserted into a whole TIN: every constraint survives as triangulation
// edges, crossings get Steiner vertices with the caller's z, the rest stays Delaunay.
#include "core/tin/constrained_rebuild.h"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "tests/support/tin_checks.h"

namespace tinbase {
namespace {

double Terrain(double x, double y) { return 200 + 0.5 * x + 0.25 * y; }
double Level(double x, double y) { return 1000 + 3 * x - y; }

// An 11 x 11 lattice with 10 m spacing, each square split by a diagonal, and one base
// constraint along the row y = 80 (from (0, 80) to (100, 80)). Built by hand, not by the
// code under test.
Tin GridTin() {
  Tin tin;
  constexpr int kN = 11;
  for (int r = 0; r < kN; ++r) {
    for (int c = 0; c < kN; ++c) {
      tin.vertices.push_back({10.0 * c, 10.0 * r, Terrain(10.0 * c, 10.0 * r)});
    }
  }
  const auto at = [](int c, int r) { return static_cast<uint32_t>(r * kN + c); };
  for (int r = 0; r + 1 < kN; ++r) {
    for (int c = 0; c + 1 < kN; ++c) {
      tin.triangles.push_back({{at(c, r), at(c + 1, r), at(c + 1, r + 1)}});
      tin.triangles.push_back({{at(c, r), at(c + 1, r + 1), at(c, r + 1)}});
    }
  }
  EXPECT_TRUE(LinkNeighbours(tin));
  tin.constraints.push_back({at(0, 8), at(10, 8)});
  tin.tags = {"granite"};
  return tin;
}

ConstraintPolyline Line(std::vector<std::pair<double, double>> xy, double z, bool closed) {
  ConstraintPolyline line;
  for (auto [x, y] : xy) line.points.push_back({x, y, z, VertexKind::kUser});
  line.closed = closed;
  return line;
}

struct Segment {
  double ax, ay, bx, by;
};

// The vertices lying on the segment (within round-off of constructed crossings), ordered from a
// to b, must be joined by constrained edges of the triangulation.
void ExpectSegmentConstrained(const Tin& tin, const Segment& s) {
  SCOPED_TRACE("segment (" + std::to_string(s.ax) + ", " + std::to_string(s.ay) + ") - (" +
               std::to_string(s.bx) + ", " + std::to_string(s.by) + ")");
  const double dx = s.bx - s.ax, dy = s.by - s.ay, len2 = dx * dx + dy * dy;
  std::vector<std::pair<double, uint32_t>> on;
  for (uint32_t v = 0; v < tin.vertices.size(); ++v) {
    const double px = tin.vertices[v].x - s.ax, py = tin.vertices[v].y - s.ay;
    const double t = (px * dx + py * dy) / len2;
    const double cross = (px * dy - py * dx) / std::sqrt(len2);
    if (t >= -1e-12 && t <= 1 + 1e-12 && std::fabs(cross) < 1e-9) on.push_back({t, v});
  }
  std::sort(on.begin(), on.end());
  ASSERT_GE(on.size(), 2u);
  EXPECT_NEAR(on.front().first, 0, 1e-12);
  EXPECT_NEAR(on.back().first, 1, 1e-12);
  std::set<std::pair<uint32_t, uint32_t>> constrained;
  for (auto [a, b] : tin.constraints) constrained.insert({std::min(a, b), std::max(a, b)});
  for (size_t i = 0; i + 1 < on.size(); ++i) {
    const uint32_t a = on[i].second, b = on[i + 1].second;
    EXPECT_TRUE(constrained.count({std::min(a, b), std::max(a, b)}))
        << "sub-edge " << a << "-" << b << " is not constrained";
  }
}

TEST(ConstrainedRebuildTest, RingAndCrossingLine) {
  const Tin base = GridTin();
  const std::vector<ConstraintPolyline> lines = {
      Line({{23.5, 27.25}, {71.5, 27.25}, {71.5, 66.75}, {23.5, 66.75}}, 500, true),  // ring
      Line({{10.5, 40.3}, {90.2, 55.7}}, 600, false),  // crosses the ring's left and right sides
      Line({{45.5, 75}, {45.5, 95}}, 700, false),      // crosses the base constraint at y = 80
      Line({{30, 10}, {60, 10}}, 800, false),          // along lattice vertices: all existing
  };
  ConstrainedRebuildMap map;
  int calls = 0;
  auto result = InsertConstraints(
      base, lines, [&](double x, double y) { return ++calls, Level(x, y); }, &map);
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  const Tin& tin = *result;

  testing::ExpectCounterClockwise(tin);
  testing::ExpectNeighboursConsistent(tin);
  testing::ExpectLocallyDelaunay(tin);
  testing::ExpectConstraintsAreEdges(tin);
  testing::ExpectEulerDisc(tin);
  for (const TinTriangle& t : tin.triangles) {
    EXPECT_TRUE(t.visible);
    EXPECT_EQ(t.tag, kNoTag);
  }
  EXPECT_EQ(tin.tags, base.tags);

  // Base vertices keep their indices and data.
  ASSERT_EQ(map.base_vertices.size(), base.vertices.size());
  for (uint32_t i = 0; i < base.vertices.size(); ++i) {
    EXPECT_EQ(map.base_vertices[i], i);
    EXPECT_EQ(tin.vertices[i].z, base.vertices[i].z);
    EXPECT_EQ(tin.vertices[i].kind, VertexKind::kDem);
  }
  // New polyline points are ring vertices with their own z; points on existing vertices map to
  // them and leave them as they were.
  ASSERT_EQ(map.line_vertices.size(), lines.size());
  for (size_t l = 0; l < 3; ++l) {
    for (size_t p = 0; p < lines[l].points.size(); ++p) {
      const TinVertex& v = tin.vertices[map.line_vertices[l][p]];
      EXPECT_GE(map.line_vertices[l][p], base.vertices.size());
      EXPECT_EQ(v.kind, VertexKind::kRing);
      EXPECT_EQ(v.x, lines[l].points[p].x);
      EXPECT_EQ(v.z, lines[l].points[p].z);
    }
  }
  EXPECT_EQ(map.line_vertices[3], (std::vector<uint32_t>{14, 17}));  // (30, 10) and (60, 10)

  // Every constraint, old and new, is a chain of constrained edges.
  ExpectSegmentConstrained(tin, {0, 80, 100, 80});
  for (const ConstraintPolyline& line : lines) {
    const size_t n = line.points.size();
    for (size_t i = 0; i + (line.closed ? 0 : 1) < n; ++i) {
      const TinVertex& a = line.points[i];
      const TinVertex& b = line.points[(i + 1) % n];
      ExpectSegmentConstrained(tin, {a.x, a.y, b.x, b.y});
    }
  }

  // Exactly the three crossings became Steiner vertices, z from the callback at their position.
  const double slope = (55.7 - 40.3) / (90.2 - 10.5);
  const std::vector<std::pair<double, double>> crossings = {
      {23.5, 40.3 + slope * (23.5 - 10.5)}, {71.5, 40.3 + slope * (71.5 - 10.5)}, {45.5, 80}};
  std::vector<uint32_t> steiner;
  for (uint32_t v = 0; v < tin.vertices.size(); ++v) {
    if (tin.vertices[v].kind == VertexKind::kSteiner) steiner.push_back(v);
  }
  ASSERT_EQ(steiner.size(), crossings.size());
  EXPECT_EQ(calls, 3);
  for (auto [x, y] : crossings) {
    bool found = false;
    for (uint32_t v : steiner) {
      const TinVertex& s = tin.vertices[v];
      if (std::hypot(s.x - x, s.y - y) < 1e-9) {
        found = true;
        EXPECT_EQ(s.z, Level(s.x, s.y));
      }
    }
    EXPECT_TRUE(found) << "no Steiner vertex at (" << x << ", " << y << ")";
  }
  const size_t new_points = 4 + 2 + 2;
  EXPECT_EQ(tin.vertices.size(), base.vertices.size() + new_points + crossings.size());
}

TEST(ConstrainedRebuildTest, NoLinesRebuildsTheBase) {
  const Tin base = GridTin();
  auto result = InsertConstraints(base, {}, Level);
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  EXPECT_EQ(result->vertices.size(), base.vertices.size());
  EXPECT_EQ(result->triangles.size(), base.triangles.size());
  ASSERT_EQ(result->constraints.size(), 10u);  // the base constraint, split at each lattice vertex
  ExpectSegmentConstrained(*result, {0, 80, 100, 80});
  testing::ExpectLocallyDelaunay(*result);
}

void CheckRebuild(const Tin& tin, const std::vector<ConstraintPolyline>& lines);

// Random polylines (some points on lattice vertices, so lines touch existing vertices and each
// other) over the grid TIN: the result is always a valid CDT holding every segment.
RC_GTEST_PROP(ConstrainedRebuildTest, RandomPolylinesAlwaysConstrained, ()) {
  const Tin base = GridTin();
  const auto point = rc::gen::oneOf(
      rc::gen::map(
          rc::gen::pair(rc::gen::inRange(-2, 13), rc::gen::inRange(-2, 13)),
          [](std::pair<int, int> p) { return std::make_pair(10.0 * p.first, 10.0 * p.second); }),
      rc::gen::map(
          rc::gen::pair(rc::gen::inRange(-150000, 1150000), rc::gen::inRange(-150000, 1150000)),
          [](std::pair<int, int> p) {
            return std::make_pair(p.first / 1e4 + 1e-7, p.second / 1e4);
          }));
  const int count = *rc::gen::inRange(1, 5);
  std::vector<ConstraintPolyline> lines;
  for (int i = 0; i < count; ++i) {
    auto xy = *rc::gen::container<std::vector<std::pair<double, double>>>(
        static_cast<size_t>(*rc::gen::inRange(2, 6)), point);
    std::set<std::pair<double, double>> distinct(xy.begin(), xy.end());
    const bool closed = distinct.size() >= 3 && *rc::gen::arbitrary<bool>();
    RC_PRE(distinct.size() >= 2);
    lines.push_back(Line(xy, 300 + i, closed));
  }
  auto result = InsertConstraints(base, lines, Level);
  RC_ASSERT(result.ok());
  const Tin& tin = *result;
  // The checks report through gtest; collect their failures so RapidCheck sees each case's own
  // verdict and can shrink.
  ::testing::TestPartResultArray failures;
  {
    ::testing::ScopedFakeTestPartResultReporter reporter(
        ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &failures);
    CheckRebuild(tin, lines);
  }
  for (int i = 0; i < failures.size(); ++i)
    RC_LOG() << failures.GetTestPartResult(i).message() << "\n";
  RC_ASSERT(failures.size() == 0);
}

void CheckRebuild(const Tin& tin, const std::vector<ConstraintPolyline>& lines) {
  testing::ExpectCounterClockwise(tin);
  testing::ExpectNeighboursConsistent(tin);
  testing::ExpectLocallyDelaunay(tin);
  testing::ExpectConstraintsAreEdges(tin);
  testing::ExpectEulerDisc(tin);
  ExpectSegmentConstrained(tin, {0, 80, 100, 80});
  for (const ConstraintPolyline& line : lines) {
    const size_t n = line.points.size();
    for (size_t i = 0; i + (line.closed ? 0 : 1) < n; ++i) {
      const TinVertex& a = line.points[i];
      const TinVertex& b = line.points[(i + 1) % n];
      if (a.x != b.x || a.y != b.y) ExpectSegmentConstrained(tin, {a.x, a.y, b.x, b.y});
    }
  }
  for (const TinVertex& v : tin.vertices) {
    if (v.kind == VertexKind::kSteiner) {
      EXPECT_EQ(v.z, Level(v.x, v.y));
    }
  }
}

TEST(ConstrainedRebuildTest, RejectsBadInput) {
  const Tin base = GridTin();
  const auto expect_invalid = [&](const std::vector<ConstraintPolyline>& lines,
                                  const ElevationFn& elevation, const std::string& needle,
                                  const Tin& from) {
    auto result = InsertConstraints(from, lines, elevation);
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(result.status().message().find(needle), std::string::npos)
        << result.status().message();
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expect_invalid({Line({{1, 1}}, 0, false)}, Level, "line 0: a constraint polyline needs", base);
  expect_invalid({Line({{1, 1}, {2, 2}}, 0, false), Line({{1, 1}, {nan, 2}}, 0, false)}, Level,
                 "line 1, point 1: coordinates are not finite", base);
  expect_invalid({Line({{1, 1}, {2, 2}, {1, 1}}, 0, true)}, Level,
                 "closed ring needs at least 3 distinct points", base);
  expect_invalid({Line({{1, 1}, {1, 1}}, 0, false)}, Level, "same x, y", base);
  expect_invalid({Line({{1, 1}, {2, 2}}, 0, false)}, nullptr, "no elevation function", base);
  Tin broken = base;
  broken.constraints.push_back({0, 5000});
  expect_invalid({}, Level, "base constraint 1 (0, 5000): no such vertex", broken);
  // A crossing where the elevation is unknown cannot get a z.
  expect_invalid(
      {Line({{5, 7}, {95, 90}}, 0, false), Line({{5, 93}, {95, 4}}, 0, false)},
      [nan](double, double) { return nan; }, "elevation there is not finite", base);
}

}  // namespace
}  // namespace tinbase
