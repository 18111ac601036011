// The XYZ reader: separators, header line, comments, and errors that name the line.
#include "core/pointcloud/xyz_reader.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/pointcloud/las_reader.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

Result<PointCloud> Parse(const std::string& text) {
  std::istringstream in(text);
  return ReadXyz(in, "pts.xyz");
}

TEST(XyzReader, WhitespaceCommasHeaderAndComments) {
  auto cloud = Parse(
      "# surveyed 2024\n"
      "X,Y,Z\n"
      "1,2,3\n"
      "\n"
      "  4.5\t5.5   6.5  \r\n"
      "# a comment between points\n"
      "-7e2, +8, 9, 255, extra\n"
      "10 ,11 , 12\n");
  ASSERT_TRUE(cloud.ok()) << cloud.status().ToString();
  ASSERT_EQ(cloud->points.size(), 4u);
  EXPECT_EQ(cloud->points[3].y, 11);
  EXPECT_EQ(cloud->points[0].x, 1);
  EXPECT_EQ(cloud->points[0].z, 3);
  EXPECT_EQ(cloud->points[1].y, 5.5);
  EXPECT_EQ(cloud->points[2].x, -700);
  EXPECT_EQ(cloud->points[2].y, 8);
  EXPECT_EQ(cloud->points[2].classification, 0);
  EXPECT_FALSE(cloud->crs.has_value());
}

TEST(XyzReader, EmptyFileHasNoPoints) {
  auto cloud = Parse("# nothing here\n\n");
  ASSERT_TRUE(cloud.ok());
  EXPECT_TRUE(cloud->points.empty());
}

TEST(XyzReader, ErrorsNameTheLine) {
  struct Case {
    std::string text;
    std::string message;
  };
  const Case cases[] = {
      {"x y z\n1 2 3\n1 2\n", "pts.xyz, line 3: expected x y z, found 2 field(s)"},
      {"1 2 3\n1 abc 3\n", "pts.xyz, line 2: y 'abc' is not a number"},
      {"1 2 3\n# c\n1 2 nan\n", "pts.xyz, line 3: z 'nan' is not finite"},
      {"1 2 3\n1 2 1e999\n", "pts.xyz, line 2: z '1e999' is not finite"},
      {"1,,3\n", "pts.xyz, line 1: y '' is not a number"},
      // A second line of names is not a header any more.
      {"x y z\nx y z\n", "pts.xyz, line 2: x 'x' is not a number"},
      {"1 2 3\n4 5 6x\n", "pts.xyz, line 2: z '6x' is not a number"},
  };
  for (const Case& c : cases) {
    auto cloud = Parse(c.text);
    ASSERT_FALSE(cloud.ok()) << c.text;
    EXPECT_EQ(cloud.status().code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(cloud.status().message(), c.message) << c.text;
  }
}

// The reader takes the input a few MiB at a time: lines that straddle a chunk's end, a last
// line without '\n' and a line number past the first chunk must come out as in one piece.
TEST(XyzReader, LinesAcrossChunksAndNoFinalNewline) {
  std::string text = "# header comment\n";
  int64_t lines = 1;
  int64_t count = 0;
  while (text.size() < (size_t{20} << 20)) {  // past two chunks
    text += std::to_string(count) + ".25 " + std::to_string(2 * count) + " 7\n";
    ++count;
    ++lines;
  }
  text += "1 2 3";  // no final newline
  ++count;
  ++lines;
  auto cloud = Parse(text);
  ASSERT_TRUE(cloud.ok()) << cloud.status().ToString();
  ASSERT_EQ(cloud->points.size(), static_cast<size_t>(count));
  for (int64_t i = 0; i + 1 < count; ++i) {
    ASSERT_EQ(cloud->points[i].x, static_cast<double>(i) + 0.25) << i;
    ASSERT_EQ(cloud->points[i].y, static_cast<double>(2 * i)) << i;
  }
  EXPECT_EQ(cloud->points.back().z, 3);

  auto bad = Parse(text + "\n4 five 6\n");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().message(),
            "pts.xyz, line " + std::to_string(lines + 1) + ": y 'five' is not a number");
}

TEST(XyzReader, MissingFile) {
  auto cloud = ReadXyz("/nonexistent/points.xyz");
  EXPECT_EQ(cloud.status().code(), StatusCode::kIOError);
}

// A real cloud written as text reads back to the same coordinates.
TEST(XyzReader, RoundTripOfRealLasPoints) {
  auto las = ReadLas(testing::DataPath("las/mvk-thin.las"));
  ASSERT_TRUE(las.ok()) << las.status().ToString();
  testing::TempDir dir;
  const std::string path = dir.Path("mvk.xyz");
  {
    std::ofstream out(path);
    out.precision(17);
    out << "x y z\n";
    for (const CloudPoint& p : las->cloud.points) out << p.x << ' ' << p.y << ' ' << p.z << '\n';
  }
  auto cloud = ReadXyz(path);
  ASSERT_TRUE(cloud.ok()) << cloud.status().ToString();
  ASSERT_EQ(cloud->points.size(), las->cloud.points.size());
  for (size_t i = 0; i < cloud->points.size(); ++i) {
    ASSERT_EQ(cloud->points[i].x, las->cloud.points[i].x) << i;
    ASSERT_EQ(cloud->points[i].y, las->cloud.points[i].y) << i;
    ASSERT_EQ(cloud->points[i].z, las->cloud.points[i].z) << i;
  }
}

}  // namespace
}  // namespace tinbase
