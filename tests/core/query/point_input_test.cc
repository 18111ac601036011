// Point input: x,y text with and without a header, comments and blank lines, the bad lines named
// by file and line, OGR point layers (reprojected), line files, and points typed on the command
// line.
#include "core/query/point_input.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

// The points of a file p.txt holding `text`.
Result<std::vector<Point2>> Text(const std::string& text) {
  TempDir dir;
  std::ofstream(dir.Path("p.txt")) << text;
  return ReadPoints(dir.Path("p.txt"));
}

void ExpectError(const Result<std::vector<Point2>>& r, const std::string& expected) {
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument) << r.status().ToString();
  EXPECT_NE(r.status().message().find(expected), std::string::npos) << r.status().message();
}

TEST(PointInput, PlainLinesCsvAndHeaders) {
  auto plain = Text("# survey\n1 2\n\n  3.5\t-4e2  99\n");
  ASSERT_TRUE(plain.ok()) << plain.status().ToString();
  ASSERT_EQ(plain->size(), 2u);
  EXPECT_EQ((*plain)[1].x, 3.5);
  EXPECT_EQ((*plain)[1].y, -400);
  auto csv = Text("1,2\n3 , 4,extra\n");
  ASSERT_TRUE(csv.ok());
  EXPECT_EQ((*csv)[1].y, 4);
  // A header picks the columns by name, in any order and case.
  auto header = Text("id,Northing,EASTING\n7,200,100\n8,201,101\n");
  ASSERT_TRUE(header.ok()) << header.status().ToString();
  ASSERT_EQ(header->size(), 2u);
  EXPECT_EQ((*header)[0].x, 100);
  EXPECT_EQ((*header)[0].y, 200);
  auto quoted = Text("\"y\",\"x\"\n1,2\n");
  ASSERT_TRUE(quoted.ok()) << quoted.status().ToString();
  EXPECT_EQ((*quoted)[0].x, 2);
  // A header naming no x and y leaves them in the first two columns.
  auto unnamed = Text("a;b\n1;2\n");
  ASSERT_TRUE(unnamed.ok()) << unnamed.status().ToString();
  EXPECT_EQ((*unnamed)[0].y, 2);
}

TEST(PointInput, BadLinesAreNamedByFileAndLine) {
  ExpectError(Text("1 2\n\n3 x4\n"), "p.txt:3: 'x4' is not a number");
  ExpectError(Text("1 2\n3\n"), "p.txt:2: expected 'x y' or 'x,y', got '3'");
  ExpectError(Text("x,y\n1,2\n3,inf\n"), "p.txt:3: coordinates must be finite");
  ExpectError(Text("x,y\n1,2\n3,nan\n"), "p.txt:3: coordinates must be finite");
  ExpectError(Text("id,x,y\n1,,3\n"), "p.txt:2: '' is not a number");
  ExpectError(Text("id,x,y\n1,2\n"), "p.txt:2: 2 field(s), the header's x and y need 3");
  ExpectError(Text("# nothing\n\n"), "p.txt: no points");
  ExpectError(Text("1 2\n1.5.5 2\n"), "p.txt:2: '1.5.5' is not a number");
}

TEST(PointInput, FilesOfTextAndOgrPointLayers) {
  TempDir dir;
  const std::string csv = dir.Path("pts.csv");
  std::ofstream(csv) << "x,y\n1,2\n3,4\n5,oops\n";
  // GDAL's CSV driver would read this file; the bad line must still be named.
  ExpectError(ReadPoints(csv), "pts.csv:4: 'oops' is not a number");

  const std::string geojson = dir.Path("pts.geojson");
  std::ofstream(geojson)
      << R"({"type":"FeatureCollection","crs":{"type":"name","properties":{"name":"EPSG:4326"}},)"
      << R"("features":[{"type":"Feature","properties":{},"geometry":{"type":"Point",)"
      << R"("coordinates":[9,0]}},{"type":"Feature","properties":{},"geometry":)"
      << R"({"type":"Point","coordinates":[9,1]}}]})";
  auto raw = ReadPoints(geojson);
  ASSERT_TRUE(raw.ok()) << raw.status().ToString();
  ASSERT_EQ(raw->size(), 2u);
  EXPECT_EQ((*raw)[1].x, 9);
  EXPECT_EQ((*raw)[1].y, 1);
  // Longitude 9 is UTM zone 32's central meridian: easting 500000 there.
  auto utm = ReadPoints(geojson, *Crs::FromUserInput("EPSG:32632"));
  ASSERT_TRUE(utm.ok()) << utm.status().ToString();
  EXPECT_NEAR((*utm)[0].x, 500000, 1e-6);
  EXPECT_NEAR((*utm)[0].y, 0, 1e-6);
  EXPECT_NEAR((*utm)[1].y, 110530.159, 0.01);  // 0.9996 of the meridian arc to 1 degree

  const std::string mixed = dir.Path("mixed.geojson");
  std::ofstream(mixed) << R"({"type":"FeatureCollection","features":[{"type":"Feature",)"
                       << R"("properties":{},"geometry":{"type":"Point","coordinates":[1,2]}},)"
                       << R"({"type":"Feature","properties":{},"geometry":{"type":"LineString",)"
                       << R"("coordinates":[[0,0],[1,1]]}}]})";
  ExpectError(ReadPoints(mixed), "mixed.geojson feature 1: geometry is a LINESTRING, not a point");

  auto missing = ReadPoints(dir.Path("nope.txt"));
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.status().code(), StatusCode::kNotFound);
  EXPECT_NE(missing.status().message().find("nope.txt"), std::string::npos);
}

TEST(PointInput, LinesFromFilesAndTheCommandLine) {
  TempDir dir;
  const std::string line = dir.Path("line.geojson");
  std::ofstream(line) << R"({"type":"FeatureCollection","features":[{"type":"Feature",)"
                      << R"("properties":{},"geometry":{"type":"LineString",)"
                      << R"("coordinates":[[0,0],[10,5],[20,0]]}}]})";
  auto read = ReadLine(line);
  ASSERT_TRUE(read.ok()) << read.status().ToString();
  ASSERT_EQ(read->size(), 3u);
  EXPECT_EQ((*read)[1].x, 10);
  EXPECT_EQ((*read)[1].y, 5);
  const std::string two = dir.Path("two.geojson");
  std::ofstream(two) << R"({"type":"FeatureCollection","features":[)"
                     << R"({"type":"Feature","properties":{},"geometry":{"type":"LineString",)"
                     << R"("coordinates":[[0,0],[1,1]]}},)"
                     << R"({"type":"Feature","properties":{},"geometry":{"type":"LineString",)"
                     << R"("coordinates":[[0,0],[1,1]]}}]})";
  ExpectError(ReadLine(two), "two.geojson: 2 line features, expected one");

  auto typed = ParsePointList(" 0,0 10,5;20,-1e1 ", "--line");
  ASSERT_TRUE(typed.ok()) << typed.status().ToString();
  ASSERT_EQ(typed->size(), 3u);
  EXPECT_EQ((*typed)[2].y, -10);
  ExpectError(ParsePointList("0,0 10;5", "--line"), "--line '0,0 10;5': point 2 '10' is not x,y");
  ExpectError(ParsePointList("0,0 1,nan", "--line"), "point 2 '1,nan' is not x,y");
  ExpectError(ParsePointList("  ", "--line"), "no points");
}

}  // namespace
}  // namespace tinbase
