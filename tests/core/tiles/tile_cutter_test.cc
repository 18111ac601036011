// TileCutter: tiles cut from one TIN meet without cracks (every pair of neighbours has the same
// vertices, quantised positions and heights along the shared edge, corners included), cover the
// surface, leave invisible triangles out, and carry unit normals of the whole surface.
#include "core/tiles/tile_cutter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "core/geometry/cdt.h"
#include "tests/support/tile_seams.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

// A Delaunay TIN over a small geographic box (degrees), heights from a smooth function, plus
// points placed exactly on and just beside level-`level` tile lines.
GeoSurface MakeSurface(int points, uint32_t seed, int level) {
  testing::RandomTinOptions options;
  options.points = points;
  options.seed = seed;
  options.x0 = 0, options.y0 = 0, options.size = 1;
  const double size = TileDegrees(level);
  const double line_x = -180.0 + std::ceil((7.1 + 180.0) / size) * size;
  const double line_y = -90.0 + std::ceil((43.6 + 90.0) / size) * size;
  // Vertices exactly on a tile line and a hair beside it, where cracks would start.
  for (double t = 0.05; t < 1; t += 0.1) {
    options.extra.emplace_back((line_x - 7.0) / 0.3, t);
    options.extra.emplace_back((line_x + 1e-9 - 7.0) / 0.3, t + 0.03);
    options.extra.emplace_back(t, (line_y - 43.5) / 0.3);
    options.extra.emplace_back(t + 0.03, (line_y - 1e-9 - 43.5) / 0.3);
  }
  Tin unit = testing::RandomDelaunayTin(options);
  GeoSurface s;
  s.tin = unit;
  for (TinVertex& v : s.tin.vertices) {
    v.x = 7.0 + 0.3 * v.x;
    v.y = 43.5 + 0.3 * v.y;
    v.z = 500 + 300 * std::sin(v.x * 40) * std::cos(v.y * 30);
  }
  s.normals = VertexNormals(s.tin);
  s.min_height = 150, s.max_height = 850;
  return s;
}

TEST(TileCutterTest, NeighbouringTilesShareTheirEdgesExactly) {
  for (const auto& [level, seed] : {std::pair{9, 5u}, {11, 5u}, {12, 5u}, {12, 6u}, {13, 7u}}) {
    const GeoSurface s = MakeSurface(3000, seed, level);
    const TileCutter cutter(s, level);
    std::map<TileKey, QuantizedMesh> tiles;
    for (const TileKey& key : cutter.Tiles()) {
      auto mesh = cutter.Cut(key);
      if (!mesh) continue;  // a triangle's box touched it, the triangle did not
      auto bytes = EncodeQuantizedMesh(*mesh);
      ASSERT_TRUE(bytes.ok()) << key.ToString() << ": " << bytes.status().ToString();
      tiles.emplace(key, std::move(*mesh));
    }
    ASSERT_GE(tiles.size(), level >= 11 ? 4u : 1u);
    const int pairs = testing::ExpectSeamsMatch(tiles);
    if (level >= 11) {
      EXPECT_GT(pairs, 2) << "level " << level;
    }
  }
}

// Sum of the tiles' plan areas in degrees squared, from their quantised triangles.
double PlanArea(const std::map<TileKey, QuantizedMesh>& tiles) {
  double area = 0;
  for (const auto& [key, m] : tiles) {
    const double scale = TileDegrees(key.level) / kQuantizedMax;
    for (size_t t = 0; t < m.triangles.size(); t += 3) {
      const uint32_t a = m.triangles[t], b = m.triangles[t + 1], c = m.triangles[t + 2];
      const double cross = (double(m.u[b]) - m.u[a]) * (double(m.v[c]) - m.v[a]) -
                           (double(m.v[b]) - m.v[a]) * (double(m.u[c]) - m.u[a]);
      EXPECT_GT(cross, 0) << key.ToString() << " triangle " << t / 3 << " is not counter-clockwise";
      area += cross / 2 * scale * scale;
    }
  }
  return area;
}

double TinArea(const Tin& tin, bool visible_only) {
  double area = 0;
  for (const TinTriangle& t : tin.triangles) {
    if (visible_only && !t.visible) continue;
    const TinVertex &a = tin.vertices[t.v[0]], &b = tin.vertices[t.v[1]], &c = tin.vertices[t.v[2]];
    area += ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)) / 2;
  }
  return area;
}

std::map<TileKey, QuantizedMesh> CutAll(const GeoSurface& s, int level) {
  const TileCutter cutter(s, level);
  std::map<TileKey, QuantizedMesh> tiles;
  for (const TileKey& key : cutter.Tiles())
    if (auto mesh = cutter.Cut(key)) tiles.emplace(key, std::move(*mesh));
  return tiles;
}

TEST(TileCutterTest, TilesCoverTheVisibleSurfaceAndLeaveHiddenTrianglesOut) {
  GeoSurface s = MakeSurface(2000, 9, 11);
  const double whole = TinArea(s.tin, false);
  EXPECT_NEAR(PlanArea(CutAll(s, 11)), whole, whole * 1e-3);
  for (size_t t = 0; t < s.tin.triangles.size(); t += 3) s.tin.triangles[t].visible = false;
  const double visible = TinArea(s.tin, true);
  ASSERT_LT(visible, whole * 0.8);
  EXPECT_NEAR(PlanArea(CutAll(s, 11)), visible, whole * 1e-3);
}

TEST(TileCutterTest, HeightsAndNormalsMatchTheSurface) {
  const GeoSurface s = MakeSurface(1500, 3, 11);
  for (const auto& [key, m] : CutAll(s, 11)) {
    ASSERT_TRUE(m.normals.has_value());
    for (size_t i = 0; i < m.vertex_count(); ++i) {
      const double h =
          s.min_height + m.height[i] / double(kQuantizedMax) * (s.max_height - s.min_height);
      EXPECT_GE(h, 500 - 300 - 1);
      EXPECT_LE(h, 500 + 300 + 1);
      double x = 0, y = 0, z = 0;
      OctDecodeNormal(&(*m.normals)[2 * i], &x, &y, &z);
      // Up, more or less, at 43.5-43.8 N, 7.0-7.3 E: the normal points away from the Earth.
      const Ecef up = ToEcef(7.15, 43.65, 0);
      const double l = std::sqrt(up[0] * up[0] + up[1] * up[1] + up[2] * up[2]);
      EXPECT_GT((x * up[0] + y * up[1] + z * up[2]) / l, 0.5) << key.ToString() << " vertex " << i;
    }
  }
}

TEST(TilingSchemeTest, LevelsAndRangesFollowCesiumsGeographicScheme) {
  EXPECT_EQ(TilesAcross(0), 2);
  EXPECT_EQ(TilesDown(0), 1);
  const TileRect r = RectOf({0, 1, 0});
  EXPECT_EQ(r.west, 0);
  EXPECT_EQ(r.east, 180);
  EXPECT_EQ(r.south, -90);
  EXPECT_EQ(r.north, 90);
  const TileRect nice = RectOf({9, 533, 383});  // the sample tile in tests/data/terrain
  EXPECT_NEAR(nice.west, 7.3828125, 1e-12);
  EXPECT_NEAR(nice.south, 44.6484375, 1e-12);
  const TileRange range = TilesMeeting(2, 0, 0, 45, 45);
  EXPECT_EQ(range.x0, 3);  // ends on the line x = 0: meets the tile west of it too
  EXPECT_EQ(range.x1, 5);
  EXPECT_EQ(range.y0, 1);
  EXPECT_EQ(range.y1, 3);
}

}  // namespace
}  // namespace tinbase
