// The STL writer's files read back through CGAL's STL reader (a reader we did not write): one
// facet per triangle, corners at the store coordinates minus the origin in the header to within
// float32 rounding, normals up.
#include "core/export/stl_writer.h"

#include <CGAL/IO/STL.h>
#include <CGAL/Simple_cartesian.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "core/export/mesh_selection.h"
#include "tests/core/export/gltf_check.h"
#include "tests/core/export/sample_tin.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using Point = CGAL::Simple_cartesian<double>::Point_3;

TEST(WriteStl, ReadsBackThroughCgalRelativeToTheRecordedOrigin) {
  const Tin tin = testing::SampleExportTin();
  auto crs = Crs::FromUserInput("EPSG:32632");
  ASSERT_TRUE(crs.ok());
  testing::TempDir dir;
  const std::string path = dir.Path("s.stl");
  const MeshSelection s = SelectTriangles(tin, false);
  ASSERT_TRUE(WriteStl(tin, &*crs, s, path).ok());

  const std::string bytes = testing::ReadBytes(path);
  ASSERT_EQ(bytes.size(), 84 + 50 * tin.triangles.size());
  const std::string header = bytes.substr(0, 80);
  EXPECT_NE(header.rfind("solid", 0), 0u);
  double x0 = 0, y0 = 0, z0 = 1;
  char label[81] = {};
  ASSERT_EQ(
      std::sscanf(header.c_str(), "tinbase STL origin %lf %lf %lf crs %80s", &x0, &y0, &z0, label),
      4)
      << header;
  EXPECT_EQ(std::string(label), "EPSG:32632");
  EXPECT_EQ(z0, 0);
  const StlOrigin origin = StlOriginOf(tin, s);
  EXPECT_EQ(x0, origin.x);
  EXPECT_EQ(y0, origin.y);
  EXPECT_EQ(x0, std::round(x0));
  EXPECT_NEAR(x0, 612345.678901234 + 6 * 30.123456789012345, 1);

  std::vector<Point> points;
  std::vector<std::array<size_t, 3>> facets;
  ASSERT_TRUE(CGAL::IO::read_STL(path, points, facets, CGAL::parameters::verbose(true)));
  ASSERT_EQ(facets.size(), tin.triangles.size());
  double worst = 0;
  for (size_t t = 0; t < facets.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const Point& p = points[facets[t][k]];
      const TinVertex& want = tin.vertices[tin.triangles[t].v[k]];
      worst = std::max({worst, std::abs(p.x() + x0 - want.x), std::abs(p.y() + y0 - want.y),
                        std::abs(p.z() - want.z)});
    }
    const Point &a = points[facets[t][0]], &b = points[facets[t][1]], &c = points[facets[t][2]];
    EXPECT_GT((b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x()), 0) << t;
  }
  // float32 near 200 m (x, y) and 1000 m (z): half an ulp is 8e-6 and 3e-5.
  EXPECT_LT(worst, 1e-4);
  EXPECT_GT(worst, 0);  // the values did go through float32
}

TEST(WriteStl, FacetNormalsAreUnitAndPointUp) {
  const Tin tin = testing::SampleExportTin();
  testing::TempDir dir;
  const std::string path = dir.Path("n.stl");
  ASSERT_TRUE(WriteStl(tin, nullptr, SelectTriangles(tin, true), path).ok());
  const std::string bytes = testing::ReadBytes(path);
  uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  EXPECT_EQ(count, SelectTriangles(tin, true).triangles.size());
  EXPECT_NE(bytes.find("crs none"), std::string::npos);
  for (uint32_t t = 0; t < count; ++t) {
    float n[3];
    std::memcpy(n, bytes.data() + 84 + 50 * t, sizeof n);
    EXPECT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0, 1e-5);
    EXPECT_GT(n[2], 0.1);
  }
}

}  // namespace
}  // namespace tinbase
