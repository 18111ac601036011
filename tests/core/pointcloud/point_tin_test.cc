// Point files to a TIN in memory: class selection, reprojection, thinning and the bulk Delaunay,
// on the real LAS files and on generated XYZ files.
#include "core/pointcloud/point_tin.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iostream>

#include "core/pointcloud/las_reader.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_checks.h"

namespace tinbase {
namespace {

using testing::DataPath;

void ExpectValidDelaunay(const Tin& tin) {
  testing::ExpectCounterClockwise(tin);
  testing::ExpectNeighboursConsistent(tin);
  testing::ExpectLocallyDelaunay(tin);
  testing::ExpectEulerDisc(tin);
  EXPECT_TRUE(tin.constraints.empty());
  for (const TinVertex& v : tin.vertices) ASSERT_EQ(v.kind, VertexKind::kLidar);
}

size_t CountClass(const std::string& relative, uint8_t c) {
  auto las = ReadLas(DataPath(relative));
  EXPECT_TRUE(las.ok());
  return static_cast<size_t>(
      std::count_if(las->cloud.points.begin(), las->cloud.points.end(),
                    [c](const CloudPoint& p) { return p.classification == c; }));
}

TEST(PointTin, AutzenDefaultsToGround) {
  auto built = BuildPointTin(DataPath("las/autzen_trim.las"), {}, std::nullopt);
  ASSERT_TRUE(built.ok()) << built.status().ToString();
  const PointTinReport& r = built->report;
  EXPECT_EQ(r.format, "LAS 1.2, point format 3");
  EXPECT_EQ(r.classes, "ground (class 2)");
  EXPECT_EQ(r.points_in, 110000u);
  EXPECT_EQ(r.selected, CountClass("las/autzen_trim.las", 2));
  EXPECT_EQ(r.kept + r.duplicates, r.selected);
  EXPECT_EQ(r.dropped, 0u);
  EXPECT_EQ(r.kept, built->tin.vertices.size());
  EXPECT_EQ(r.triangles, built->tin.triangles.size());
  EXPECT_TRUE(r.reprojected_from.empty());
  ASSERT_TRUE(built->crs.has_value());
  EXPECT_FALSE(built->crs->IsGeographic());
  ExpectValidDelaunay(built->tin);
  std::cout << "autzen ground: " << r.selected << " points, " << r.duplicates << " duplicates, "
            << r.triangles << " triangles\n";
}

TEST(PointTin, ExplicitClassesAndNoGroundClass) {
  PointTinOptions o;
  o.classes = {1, 2};
  auto built = BuildPointTin(DataPath("las/autzen_trim.las"), o, std::nullopt);
  ASSERT_TRUE(built.ok());
  EXPECT_EQ(built->report.classes, "classes 1 2");
  EXPECT_EQ(built->report.selected,
            CountClass("las/autzen_trim.las", 1) + CountClass("las/autzen_trim.las", 2));

  // mvk-thin: whatever its classes, the default takes ground when there is any, else everything.
  auto mvk = BuildPointTin(DataPath("las/mvk-thin.las"), {}, std::nullopt);
  ASSERT_TRUE(mvk.ok()) << mvk.status().ToString();
  const size_t ground = CountClass("las/mvk-thin.las", 2);
  EXPECT_EQ(mvk->report.selected, ground > 0 ? ground : 6280u);
  EXPECT_EQ(mvk->report.classes,
            ground > 0 ? "ground (class 2)" : "all points (no point has class 2)");
  std::cout << "mvk-thin default selection: " << mvk->report.classes << ", " << mvk->report.selected
            << " points\n";
  ExpectValidDelaunay(mvk->tin);
}

TEST(PointTin, ReprojectsToTheTarget) {
  // 4_6_crop is a 200 x 200 US-foot tile in New Mexico Central (EPSG:2903); in UTM 13N it must
  // be a ~61 m square (a little more across: the grids are rotated against each other).
  auto target = Crs::FromUserInput("EPSG:32613");
  ASSERT_TRUE(target.ok());
  PointTinOptions all;
  all.classes = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  auto built = BuildPointTin(DataPath("las/4_6_crop.las"), all, *target);
  ASSERT_TRUE(built.ok()) << built.status().ToString();
  auto in_feet = BuildPointTin(DataPath("las/4_6_crop.las"), all, std::nullopt);
  ASSERT_TRUE(in_feet.ok()) << in_feet.status().ToString();
  EXPECT_EQ(built->report.reprojected_from, "EPSG:2903");
  ASSERT_TRUE(built->crs && built->crs->IsSame(*target));
  double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
  for (const TinVertex& v : built->tin.vertices) {
    xmin = std::min(xmin, v.x);
    xmax = std::max(xmax, v.x);
    ymin = std::min(ymin, v.y);
    ymax = std::max(ymax, v.y);
  }
  // Heights follow into metres: EPSG:2903 is in US survey feet (1200 / 3937 m), UTM in metres.
  ASSERT_EQ(built->tin.vertices.size(), in_feet->tin.vertices.size());
  auto by_z = [](const TinVertex& a, const TinVertex& b) { return a.z < b.z; };
  std::vector<TinVertex> metres = built->tin.vertices, feet = in_feet->tin.vertices;
  std::sort(metres.begin(), metres.end(), by_z);
  std::sort(feet.begin(), feet.end(), by_z);
  for (size_t i = 0; i < metres.size(); ++i)
    EXPECT_NEAR(metres[i].z, feet[i].z * 1200.0 / 3937.0, 1e-6) << i;
  EXPECT_GT(feet.front().z, 7000);
  EXPECT_NEAR(xmax - xmin, 61, 2.5);
  EXPECT_NEAR(ymax - ymin, 61, 2.5);
  // Albuquerque area, UTM 13N.
  EXPECT_GT(xmin, 300000);
  EXPECT_LT(xmax, 400000);
  EXPECT_GT(ymin, 3850000);
  EXPECT_LT(ymax, 3950000);
  ExpectValidDelaunay(built->tin);
}

TEST(PointTin, ThinningShrinksTheTin) {
  auto plain = BuildPointTin(DataPath("las/autzen_trim.las"), {}, std::nullopt);
  PointTinOptions o;
  o.thin = true;
  o.thinning.max_cell_area = 15;
  o.thinning.vertical_threshold = 0.15;
  auto thinned = BuildPointTin(DataPath("las/autzen_trim.las"), o, std::nullopt);
  ASSERT_TRUE(plain.ok() && thinned.ok()) << thinned.status().ToString();
  const PointTinReport& r = thinned->report;
  EXPECT_GT(r.dropped, 0u);
  EXPECT_EQ(r.kept + r.dropped + r.duplicates, r.selected);
  EXPECT_EQ(r.duplicates, plain->report.duplicates);
  EXPECT_EQ(r.kept, plain->report.kept - r.dropped);
  EXPECT_LT(r.triangles, plain->report.triangles);
  EXPECT_EQ(r.cell_area_threshold, 15);
  ExpectValidDelaunay(thinned->tin);
  std::cout << "autzen ground thinned: " << r.selected << " -> " << r.kept << " points, "
            << plain->report.triangles << " -> " << r.triangles << " triangles\n";
}

TEST(PointTin, XyzFileHasNoCrsUnlessTheTargetGivesOne) {
  testing::TempDir dir;
  const std::string path = dir.Path("pts.txt");
  {
    std::ofstream out(path);
    out << "x,y,z\n";
    for (int i = 0; i < 10; ++i) {
      for (int j = 0; j < 10; ++j)
        out << i * 3 + (j % 2) * 0.5 << "," << j * 3 << "," << i + j << "\n";
    }
    out << "0,0,42\n";  // a duplicate of the first point
  }
  auto built = BuildPointTin(path, {}, std::nullopt);
  ASSERT_TRUE(built.ok()) << built.status().ToString();
  EXPECT_EQ(built->report.format, "XYZ");
  EXPECT_EQ(built->report.classes, "all points (no point has class 2)");
  EXPECT_FALSE(built->crs.has_value());
  EXPECT_EQ(built->report.selected, 101u);
  EXPECT_EQ(built->report.duplicates, 1u);
  EXPECT_EQ(built->report.kept, 100u);
  EXPECT_EQ(built->tin.vertices[0].z, 0) << "the first of two duplicates is kept";
  ExpectValidDelaunay(built->tin);

  // A store CRS and a file without one: the points are taken to be in the store's CRS.
  auto utm = Crs::FromUserInput("EPSG:32632");
  auto in_store = BuildPointTin(path, {}, *utm);
  ASSERT_TRUE(in_store.ok());
  EXPECT_TRUE(in_store->report.reprojected_from.empty());
  EXPECT_EQ(in_store->tin.vertices[1].x, built->tin.vertices[1].x);
}

// ReadPoints hands the points over sorted by x, then y, without duplicates (the first in file
// order stays), and BuildPointTin's TIN has exactly those vertices.
TEST(PointTin, ReadPointsSortsAndDropsDuplicatesKeepingTheFirst) {
  testing::TempDir dir;
  const std::string path = dir.Path("pts.xyz");
  {
    std::ofstream out(path);
    out << "5 0 1\n0 5 2\n0 0 3\n5 5 4\n0 0 5\n2 2 6\n5 0 7\n";
  }
  auto points = ReadPoints(path, {}, std::nullopt);
  ASSERT_TRUE(points.ok()) << points.status().ToString();
  EXPECT_EQ(points->report.selected, 7u);
  EXPECT_EQ(points->report.duplicates, 2u);
  const std::vector<std::array<double, 3>> expected = {
      {0, 0, 3}, {0, 5, 2}, {2, 2, 6}, {5, 0, 1}, {5, 5, 4}};
  ASSERT_EQ(points->vertices.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(points->vertices[i].x, expected[i][0]) << i;
    EXPECT_EQ(points->vertices[i].y, expected[i][1]) << i;
    EXPECT_EQ(points->vertices[i].z, expected[i][2]) << i;
    EXPECT_EQ(points->vertices[i].kind, VertexKind::kLidar) << i;
  }
  auto built = BuildPointTin(path, {}, std::nullopt);
  ASSERT_TRUE(built.ok()) << built.status().ToString();
  ASSERT_EQ(built->tin.vertices.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(built->tin.vertices[i].z, expected[i][2]);
  EXPECT_EQ(built->report.kept, 5u);
  EXPECT_EQ(built->report.triangles, 4u);
}

// Large files sort in two halves on two threads: the result must still be the stable order,
// with the first of each duplicate in file order kept, whether its copies lie in the same half
// or in the other one.
TEST(PointTin, LargeFilesSortAndDropDuplicatesAsSmallOnes) {
  testing::TempDir dir;
  const std::string path = dir.Path("many.xyz");
  constexpr int kSide = 400;              // 160 000 distinct points, then copies
  std::vector<std::array<int, 3>> lines;  // x, y, z (z = line number, to tell copies apart)
  for (int i = 0; i < kSide * kSide; ++i) {
    const int k = static_cast<int>((static_cast<int64_t>(i) * 7919) % (kSide * kSide));
    lines.push_back({k % kSide, k / kSide, 0});
  }
  // Copies of points from the first half appended at the end (the other half), and copies of
  // second-half points placed right after them (the same half).
  for (int i = 0; i < 3000; ++i) lines.push_back(lines[static_cast<size_t>(i) * 17]);
  for (int i = 0; i < 3000; ++i)
    lines.insert(lines.begin() + 100000 + i * 2, lines[99000 + static_cast<size_t>(i) * 2]);
  {
    std::ofstream out(path);
    for (size_t i = 0; i < lines.size(); ++i)
      out << lines[i][0] << ' ' << lines[i][1] << ' ' << i << '\n';
  }
  auto points = ReadPoints(path, {}, std::nullopt);
  ASSERT_TRUE(points.ok()) << points.status().ToString();
  EXPECT_EQ(points->report.duplicates, 6000u);
  ASSERT_EQ(points->vertices.size(), static_cast<size_t>(kSide * kSide));
  std::vector<double> first_line(static_cast<size_t>(kSide * kSide), -1);
  for (size_t i = 0; i < lines.size(); ++i) {
    double& first = first_line[static_cast<size_t>(lines[i][0]) * kSide + lines[i][1]];
    if (first < 0) first = static_cast<double>(i);
  }
  for (size_t i = 0; i < points->vertices.size(); ++i) {
    const TinVertex& v = points->vertices[i];
    const size_t row = i / kSide;  // the grid row of the i-th point, whole
    ASSERT_EQ(v.x, static_cast<double>(row)) << i;
    ASSERT_EQ(v.y, static_cast<double>(i % kSide)) << i;
    ASSERT_EQ(v.z, first_line[i]) << "the first of the copies in file order is kept, at " << i;
  }
}

TEST(PointTin, ErrorsNameTheFile) {
  PointTinOptions none;
  none.classes = {31};
  auto empty = BuildPointTin(DataPath("las/mvk-thin.las"), none, std::nullopt);
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.status().message().find("mvk-thin.las: the 0 points of classes 31 span no "
                                          "triangle"),
            std::string::npos)
      << empty.status().message();

  testing::TempDir dir;
  const std::string laz = dir.Path("cloud.laz");
  std::ofstream(laz) << "LASF";
  auto refused = BuildPointTin(laz, {}, std::nullopt);
  EXPECT_NE(refused.status().message().find("is LAZ (compressed)"), std::string::npos);

  const std::string bad = dir.Path("bad.xyz");
  std::ofstream(bad) << "1 2 3\n4 5 six\n";
  EXPECT_EQ(BuildPointTin(bad, {}, std::nullopt).status().message(),
            bad + ", line 2: z 'six' is not a number");

  const std::string nan = dir.Path("nan.csv");
  std::ofstream(nan) << "1,2,3\n4,5,nan\n";
  EXPECT_NE(BuildPointTin(nan, {}, std::nullopt).status().message().find("line 2"),
            std::string::npos);
}

}  // namespace
}  // namespace tinbase
