// Draping a polyline: "no data here" (NaN) is the user's problem and says where; an elevation
// that could not be read is the store's problem and comes back as its own error, never as
// "no elevation".
#include "core/tin/drape.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace tinbase {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(DrapeTest, APlaneNeedsNoExtraVerticesAndTakesItsZ) {
  const DrapeElevationFn plane = [](double x, double y) -> Result<double> { return x + 2 * y; };
  auto draped = DrapePolyline({{0, 0}, {100, 0}, {100, 50}}, plane, {.tolerance = 0.1});
  ASSERT_TRUE(draped.ok()) << draped.status().ToString();
  ASSERT_EQ(draped->size(), 3u);
  EXPECT_DOUBLE_EQ((*draped)[2].z, 200);
  for (const TinVertex& v : *draped) EXPECT_EQ(v.kind, VertexKind::kRing);
}

TEST(DrapeTest, ABumpIsFollowedToTheTolerance) {
  const DrapeElevationFn bump = [](double x, double) -> Result<double> {
    return 10 * std::exp(-(x - 50) * (x - 50) / 200);
  };
  auto draped = DrapePolyline({{0, 0}, {100, 0}}, bump, {.tolerance = 0.5, .min_spacing = 1});
  ASSERT_TRUE(draped.ok()) << draped.status().ToString();
  EXPECT_GT(draped->size(), 4u);
  for (size_t i = 1; i < draped->size(); ++i) EXPECT_LT((*draped)[i - 1].x, (*draped)[i].x);
}

TEST(DrapeTest, NoDataIsInvalidArgumentNamingTheVertex) {
  const DrapeElevationFn holed = [](double x, double) -> Result<double> {
    return x > 150 ? kNaN : 1.0;
  };
  auto at_vertex = DrapePolyline({{0, 0}, {100, 0}, {200, 0}}, holed, {});
  ASSERT_FALSE(at_vertex.ok());
  EXPECT_EQ(at_vertex.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(at_vertex.status().message().find("vertex 2: no elevation at"), std::string::npos)
      << at_vertex.status().message();
}

TEST(DrapeTest, AReadFailureKeepsItsCodeAndMessage) {
  const Status broken =
      Status::Corruption("DEM 'd', level 0 block (1, 0): block fails its checksum");
  // At an input vertex.
  const DrapeElevationFn at_x100 = [&](double x, double) -> Result<double> {
    if (x == 100) return broken;
    return 1.0;
  };
  auto vertex = DrapePolyline({{0, 0}, {100, 0}}, at_x100, {});
  ASSERT_FALSE(vertex.ok());
  EXPECT_EQ(vertex.status().code(), StatusCode::kCorruption);
  EXPECT_EQ(vertex.status().message(), "vertex 1: " + broken.message());
  // At a point the densification asks for between two vertices.
  const DrapeElevationFn between = [&](double x, double) -> Result<double> {
    if (x > 0 && x < 100) return broken;
    return 1.0;
  };
  auto inserted = DrapePolyline({{0, 0}, {100, 0}}, between, {});
  ASSERT_FALSE(inserted.ok());
  EXPECT_EQ(inserted.status().code(), StatusCode::kCorruption);
  EXPECT_EQ(inserted.status().message(), "vertex 0: " + broken.message());
}

}  // namespace
}  // namespace tinbase
