// ProfileAlong on a stored plane, whose z is known everywhere: every station's z, the length,
// the tag and visibility of each stretch by where it lies, and the bad lines refused.
#include "db/query/profile.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/db/query/query_fixture.h"
#include "tests/support/grid_tin.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::PlaneZ;
using testing::TempDir;

constexpr double kX0 = 500000, kY0 = 5000000, kCell = 10;

// 20 x 10 cells; triangles west of x0 + 100 tagged "sand", east of it "clay"; those whose
// centroid lies in column 15 hidden.
Tin PaintedPlane() {
  Tin tin = testing::MakeGridTin(20, 10, kCell, kX0, kY0, PlaneZ);
  tin.tags = {"sand", "clay"};
  for (TinTriangle& t : tin.triangles) {
    double cx = 0;
    for (uint32_t v : t.v) cx += tin.vertices[v].x / 3;
    t.tag = cx < kX0 + 100 ? 0 : 1;
    t.visible = !(cx > kX0 + 150 && cx < kX0 + 160);
  }
  return tin;
}

class ProfileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto stored =
        testing::StoreSurface(testing::StoreTarget(dir_, "p.tinbase"), "plane", PaintedPlane());
    ASSERT_TRUE(stored.ok()) << stored.status().ToString();
    s_ = std::move(*stored);
  }
  TempDir dir_;
  testing::StoredSurface s_;
};

TEST_F(ProfileTest, StationsLieOnThePlaneAndStretchesCarryTheirPaint) {
  const std::vector<Point2> line = {
      {kX0 + 5, kY0 + 5}, {kX0 + 195, kY0 + 95}, {kX0 + 195.5, kY0 + 3}};
  auto p = ProfileAlong(*s_.store, s_.info, line);
  ASSERT_TRUE(p.ok()) << p.status().ToString();
  ASSERT_EQ(p->stretches.size() + 1, p->stations.size());
  const double length = std::hypot(190, 90) + std::hypot(0.5, 92);
  EXPECT_NEAR(p->length(), length, 1e-9);
  // The first segment crosses 19 vertical and 8 horizontal grid lines and a diagonal in most
  // of the cells it passes through: dozens of stations, each on the plane.
  EXPECT_GT(p->stations.size(), 40u);
  for (const Station& st : p->stations) EXPECT_NEAR(st.z, PlaneZ(st.x, st.y), 1e-9);
  int hidden = 0;
  for (size_t i = 0; i < p->stretches.size(); ++i) {
    const double mx = (p->stations[i].x + p->stations[i + 1].x) / 2;
    const ProfileStretch& r = p->stretches[i];
    // A stretch lies in its triangle, and every triangle lies within one column of cells, so the
    // middle of a stretch tells its paint.
    ASSERT_TRUE(r.tag.has_value());
    EXPECT_EQ(*r.tag, mx < kX0 + 100 ? "sand" : "clay") << "stretch " << i;
    EXPECT_EQ(r.visible, !(mx > kX0 + 150 && mx < kX0 + 160)) << "stretch " << i;
    hidden += r.visible ? 0 : 1;
  }
  EXPECT_GT(hidden, 0);
  EXPECT_EQ(p->stations.front().kind, StationKind::kStart);
  EXPECT_EQ(p->stations.back().kind, StationKind::kEnd);
}

TEST_F(ProfileTest, ALineAlongGridEdgesPassesThroughTheVertices) {
  auto p = ProfileAlong(*s_.store, s_.info, {{kX0, kY0 + 50}, {kX0 + 200, kY0 + 50}});
  ASSERT_TRUE(p.ok()) << p.status().ToString();
  // From a boundary vertex to a boundary vertex through the 19 vertices between.
  ASSERT_EQ(p->stations.size(), 21u);
  for (size_t k = 1; k + 1 < p->stations.size(); ++k) {
    EXPECT_EQ(p->stations[k].kind, StationKind::kVertex);
    EXPECT_EQ(p->stations[k].x, kX0 + 10.0 * static_cast<double>(k));
    EXPECT_EQ(p->stations[k].distance, 10.0 * static_cast<double>(k));
    EXPECT_EQ(p->stations[k].z, PlaneZ(p->stations[k].x, kY0 + 50));
  }
}

TEST_F(ProfileTest, BadLinesAreRefusedNamingTheProblem) {
  const auto expect = [&](const std::vector<Point2>& line, StatusCode code,
                          const std::string& text) {
    auto p = ProfileAlong(*s_.store, s_.info, line);
    ASSERT_FALSE(p.ok());
    EXPECT_EQ(p.status().code(), code) << p.status().ToString();
    EXPECT_NE(p.status().message().find(text), std::string::npos) << p.status().message();
  };
  expect({}, StatusCode::kInvalidArgument, "at least two points, got 0");
  expect({{kX0 + 5, kY0 + 5}}, StatusCode::kInvalidArgument, "at least two points, got 1");
  expect({{kX0 + 5, kY0 + 5}, {kX0 + 5, kY0 + 5}}, StatusCode::kInvalidArgument,
         "all its points are the same");
  expect({{kX0 + 5, kY0 + 5}, {NAN, kY0}}, StatusCode::kInvalidArgument,
         "profile point 2 is not finite");
  expect({{kX0 - 5, kY0 + 5}, {kX0 + 5, kY0 + 5}}, StatusCode::kNotFound,
         "profile point 1: point (499995, 5000005) is outside surface 'plane'");
  expect({{kX0 + 5, kY0 + 5}, {kX0 + 5, kY0 + 50}, {kX0 + 5, kY0 + 500}},
         StatusCode::kInvalidArgument,
         "the line leaves the surface at (500005, 5000100) on its way to point 3");
}

}  // namespace
}  // namespace tinbase
