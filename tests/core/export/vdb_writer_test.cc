// The OpenVDB writer on analytic pairs: the volume a written grid encloses (read back from the
// file) matches the TIN's own volume within 1 %, for a fog volume between two planes, between a
// plane and a paraboloid, and for a level set of a paraboloid over a floor; OpenVDB's vdb_print
// reads every file; bad options are rejected.
#include "core/export/vdb_writer.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include "tests/support/grid_tin.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

// A surface over [0, 200] x [0, 100] in UTM-sized coordinates (so float precision would show),
// cells of 4.
constexpr double kX0 = 612000, kY0 = 5171000;
Tin Surface(const std::function<double(double, double)>& z) {
  return testing::MakeGridTin(50, 25, 4.0, kX0, kY0,
                              [&](double x, double y) { return z(x - kX0, y - kY0); });
}

double Area(const Tin& tin, const TinTriangle& t) {
  const TinVertex &a = tin.vertices[t.v[0]], &b = tin.vertices[t.v[1]], &c = tin.vertices[t.v[2]];
  return 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
}

// The TIN volume of top - base for two TINs of one triangulation: the difference is linear on
// each triangle, so the volume is exactly area times the mean of the three differences.
double TinVolumeBetween(const Tin& top, const Tin& base) {
  double v = 0;
  for (const TinTriangle& t : top.triangles) {
    double mean = 0;
    for (uint32_t i : t.v) mean += (top.vertices[i].z - base.vertices[i].z) / 3;
    v += Area(top, t) * mean;
  }
  return v;
}

// Runs `command`; returns its exit status and sets *out to what it printed.
int Run(const std::string& command, std::string* out) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return -1;
  std::array<char, 4096> buf{};
  out->clear();
  for (size_t n; (n = fread(buf.data(), 1, buf.size(), pipe)) > 0;) out->append(buf.data(), n);
  return pclose(pipe);
}

// OpenVDB's own vdb_print must read the file (Debian: libopenvdb-tools); a missing tool fails.
void ExpectVdbPrintReads(const std::string& path, const std::string& grid_name) {
  std::string out;
  ASSERT_EQ(Run("command -v vdb_print", &out), 0)
      << "vdb_print is not installed (Debian package libopenvdb-tools)";
  ASSERT_EQ(Run("vdb_print -l '" + path + "'", &out), 0) << out;
  EXPECT_NE(out.find(grid_name), std::string::npos) << out;
}

TEST(VdbWriterTest, FogVolumeBetweenTwoPlanesMatchesTheTinVolume) {
  TempDir dir;
  const Tin top = Surface([](double x, double y) { return 50 + 0.1 * x + 0.05 * y; });
  const Tin base = Surface([](double x, double y) { return 10 + 0.02 * x - 0.03 * y; });
  VdbOptions options;
  options.voxel = 1.0;
  const std::string path = dir.Path("planes.vdb");
  auto report = WriteThicknessFogVolume(top, base, options, path);
  ASSERT_TRUE(report.ok()) << report.status().message();
  const double expected = TinVolumeBetween(top, base);
  auto read = MeasureVdb(path);
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_EQ(read->grid_class, "fog volume");
  EXPECT_NEAR(read->volume, expected, 0.01 * expected);
  EXPECT_NEAR(report->volume, read->volume, 1e-6 * expected);
  ExpectVdbPrintReads(path, "thickness");
}

TEST(VdbWriterTest, FogVolumeBetweenAPlaneAndAParaboloidMatchesTheTinVolume) {
  TempDir dir;
  const Tin top = Surface([](double x, double) { return 60 + 0.05 * x; });
  const Tin base = Surface(
      [](double x, double y) { return 0.002 * ((x - 100) * (x - 100) + (y - 50) * (y - 50)); });
  VdbOptions options;
  options.voxel = 0.75;
  options.name = "formation";
  const std::string path = dir.Path("bowl.vdb");
  ASSERT_TRUE(WriteThicknessFogVolume(top, base, options, path).ok());
  const double expected = TinVolumeBetween(top, base);
  auto read = MeasureVdb(path);
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_NEAR(read->volume, expected, 0.01 * expected);
  ExpectVdbPrintReads(path, "formation");
}

TEST(VdbWriterTest, LevelSetOfAParaboloidOverAFloorMatchesTheTinVolume) {
  TempDir dir;
  const Tin surface = Surface([](double x, double y) {
    return 40 - 0.002 * ((x - 100) * (x - 100) + (y - 50) * (y - 50));
  });
  const double floor = 5;
  const Tin flat = Surface([&](double, double) { return floor; });
  VdbOptions options;
  options.voxel = 1.0;
  options.floor = floor;
  const std::string path = dir.Path("hill.vdb");
  ASSERT_TRUE(WriteSurfaceLevelSet(surface, options, path).ok());
  const double expected = TinVolumeBetween(surface, flat);
  auto read = MeasureVdb(path);
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_EQ(read->grid_class, "level set");
  EXPECT_NEAR(read->volume, expected, 0.01 * expected);
  ExpectVdbPrintReads(path, "surface");
}

TEST(VdbWriterTest, HiddenTrianglesAreLeftOut) {
  TempDir dir;
  Tin top = Surface([](double, double) { return 20; });
  const Tin base = Surface([](double, double) { return 0; });
  const double all = TinVolumeBetween(top, base);
  for (size_t t = 0; t < top.triangles.size() / 2; ++t) top.triangles[t].visible = false;
  VdbOptions options;
  options.voxel = 1.0;
  ASSERT_TRUE(WriteThicknessFogVolume(top, base, options, dir.Path("half.vdb")).ok());
  auto read = MeasureVdb(dir.Path("half.vdb"));
  ASSERT_TRUE(read.ok());
  EXPECT_NEAR(read->volume, all / 2, 0.02 * all);
}

TEST(VdbWriterTest, RejectsBadOptions) {
  TempDir dir;
  const Tin top = Surface([](double, double) { return 20; });
  const Tin base = Surface([](double, double) { return 0; });
  const auto message = [](const auto& r) { return r.ok() ? std::string() : r.status().message(); };
  VdbOptions options;
  options.voxel = -1;
  EXPECT_NE(message(WriteThicknessFogVolume(top, base, options, dir.Path("a.vdb")))
                .find("not a positive number"),
            std::string::npos);
  options.voxel = 0.01;
  options.max_voxels = 1000000;
  EXPECT_NE(message(WriteThicknessFogVolume(top, base, options, dir.Path("a.vdb")))
                .find("give a larger --voxel"),
            std::string::npos);
  options = VdbOptions{};
  options.floor = 25;
  EXPECT_NE(message(WriteSurfaceLevelSet(top, options, dir.Path("a.vdb"))).find("below"),
            std::string::npos);
  Tin away = base;
  for (TinVertex& v : away.vertices) v.x += 1000;
  EXPECT_NE(message(WriteThicknessFogVolume(top, away, VdbOptions{}, dir.Path("a.vdb")))
                .find("do not overlap"),
            std::string::npos);
  Tin hidden = top;
  for (TinTriangle& t : hidden.triangles) t.visible = false;
  EXPECT_NE(message(WriteSurfaceLevelSet(hidden, VdbOptions{}, dir.Path("a.vdb")))
                .find("no visible triangle"),
            std::string::npos);
  EXPECT_FALSE(MeasureVdb(dir.Path("missing.vdb")).ok());
}

}  // namespace
}  // namespace tinbase
