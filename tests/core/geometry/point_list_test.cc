// Reading plan points from text: separators, comments, a CSV header, and bad lines by number.
#include "core/geometry/point_list.h"

#include <gtest/gtest.h>

#include <sstream>

namespace tinbase {
namespace {

Result<std::vector<Point2>> Read(const std::string& text) {
  std::istringstream in(text);
  return ReadPointList(in, "pts");
}

TEST(PointListTest, SeparatorsCommentsAndHeader) {
  auto points = Read("x;y\n# comment\n\n1 2\n3,4,extra\n  5\t6\r\n+7;-8.5e1\n");
  ASSERT_TRUE(points.ok()) << points.status().ToString();
  ASSERT_EQ(points->size(), 4u);
  EXPECT_EQ((*points)[0].x, 1);
  EXPECT_EQ((*points)[1].y, 4);
  EXPECT_EQ((*points)[2].x, 5);
  EXPECT_EQ((*points)[2].y, 6);
  EXPECT_EQ((*points)[3].x, 7);
  EXPECT_EQ((*points)[3].y, -85);
  EXPECT_TRUE(Read("").ok());
  EXPECT_TRUE(Read("").value().empty());
}

TEST(PointListTest, AHeaderNamingXAndYPicksThoseColumns) {
  auto points = Read("id,name,Northing,EASTING\n1,,200,100\n2,well b,201.5,101\n");
  ASSERT_TRUE(points.ok()) << points.status().ToString();
  ASSERT_EQ(points->size(), 2u);
  EXPECT_EQ((*points)[0].x, 100);
  EXPECT_EQ((*points)[0].y, 200);
  EXPECT_EQ((*points)[1].y, 201.5);
  auto spaced = Read("z y x\n5 2 1\n");
  ASSERT_TRUE(spaced.ok()) << spaced.status().ToString();
  EXPECT_EQ((*spaced)[0].x, 1);
  // An empty field is a column: x is not taken from the next one.
  auto empty = Read("id,x,y\n1,,3\n");
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.status().message().find("pts:2: '' is not a number"), std::string::npos)
      << empty.status().message();
  auto short_line = Read("id,x,y\n1,2\n");
  ASSERT_FALSE(short_line.ok());
  EXPECT_NE(short_line.status().message().find("pts:2: 2 field(s), the header's x and y need 3"),
            std::string::npos)
      << short_line.status().message();
}

TEST(PointListTest, BadLinesNameTheLine) {
  struct Case {
    const char* text;
    const char* message;
  } cases[] = {
      {"1 2\n3\n", "pts:2: expected 'x y' or 'x,y', got '3'"},
      {"1 2\n3 y\n", "pts:2: 'y' is not a number"},
      {"x y\n1 2\nx y\n", "pts:3: 'x' is not a number"},  // only a first line is a header
      {"1 nan\n", "pts:1: coordinates must be finite"},
      {"1 inf\n", "pts:1: coordinates must be finite"},
      {"1.5.2 3\n", "pts:1: '1.5.2' is not a number"},
  };
  for (const Case& c : cases) {
    auto points = Read(c.text);
    ASSERT_FALSE(points.ok()) << c.text;
    EXPECT_EQ(points.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(points.status().message().find(c.message), std::string::npos)
        << points.status().message();
  }
}

}  // namespace
}  // namespace tinbase
