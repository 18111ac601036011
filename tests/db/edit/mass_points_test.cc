// Mass points (db/edit/mass_points.h) on the Hamersley greedy surface: survey points go in with
// their own z as `user` vertices of one `points` feature, snapped ones are reported, points
// outside are refused with the store unchanged, and `points remove` takes them out again (whole
// feature or by box), every state passing `check --full`.
#include "db/edit/mass_points.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "db/point_locator.h"
#include "tests/support/edit_fixture.h"
#include "tests/support/store_target.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::EditFixture;
using testing::ExpectStoreIntact;
using testing::kEditCell;
using testing::kEditCx;
using testing::kEditCy;
using testing::TableChecksums;

class MassPoints : public EditFixture {
 protected:
  // `n` points in a square of `half` cells around the centre, z = DEM + offset, seeded.
  std::vector<TinVertex> Shots(int n, double half, double offset, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-half * kEditCell, half * kEditCell);
    std::vector<TinVertex> out;
    while (static_cast<int>(out.size()) < n) {
      const double x = kEditCx + u(rng), y = kEditCy + u(rng);
      auto z = dems_->Sample(dem_, x, y);
      if (!z.ok() || std::isnan(*z)) continue;
      out.push_back({x, y, *z + offset, VertexKind::kUser});
    }
    return out;
  }

  static std::vector<std::string> Labels(size_t n) {
    std::vector<std::string> labels;
    for (size_t i = 0; i < n; ++i) labels.push_back("shots, point " + std::to_string(i + 1));
    return labels;
  }

  Result<PointsReport> Add(const std::vector<TinVertex>& points) {
    PointsAddOptions o;
    o.surface = "terrain";
    o.points = points;
    o.labels = Labels(points.size());
    return AddPoints(*store_, o);
  }

  int64_t Count(const std::string& sql) {
    auto stmt = store_->db().Cached(sql);
    EXPECT_TRUE(stmt.ok());
    auto row = (*stmt)->Step();
    EXPECT_TRUE(row.ok() && *row);
    const int64_t n = (*stmt)->ColumnInt(0);
    (*stmt)->Reset();
    return n;
  }

  std::string Path() { return testing::StoreTarget(dir_, "s.tinbase"); }
};

TEST_F(MassPoints, PointsGoInWithTheirOwnZAsOneFeatureAndOneChange) {
  const int64_t changes = Count("SELECT COUNT(*) FROM changes");
  const std::vector<TinVertex> shots = Shots(60, 20, 3.0, 7);
  auto report = Add(shots);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->inserted, 60);
  EXPECT_TRUE(report->snapped.empty());
  ASSERT_EQ(report->features_added.size(), 1u);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM changes"), changes + 1);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM changes WHERE action = 'points add' AND feature = " +
                  std::to_string(report->features_added[0])),
            1);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM vertices WHERE kind = 'user'"), 60);
  ASSERT_TRUE(ReloadSurface());
  auto feature = LoadFeature(*store_, surface_, report->features_added[0]);
  ASSERT_TRUE(feature.ok()) << feature.status().ToString();
  EXPECT_EQ(feature->mode, FeatureMode::kPoints);
  ASSERT_EQ(feature->points.size(), shots.size());
  for (size_t i = 0; i < shots.size(); ++i) {
    EXPECT_EQ(feature->points[i].x, shots[i].x);  // file order, bit for bit
    auto at = LocatePoint(*store_, surface_, shots[i].x, shots[i].y);
    ASSERT_TRUE(at.ok());
    EXPECT_NEAR(at->z, shots[i].z, 1e-6) << "point " << i;
  }
  ExpectStoreIntact(*store_, /*full=*/true);
}

TEST_F(MassPoints, PointsFarFromTheDemAreRefinedAroundToTheTolerance) {
  auto report = Add(Shots(25, 15, 40.0, 11));
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->inserted, 25);
  EXPECT_GT(report->refinement_points, 0);
  ExpectStoreIntact(*store_, /*full=*/true);
}

TEST_F(MassPoints, PointsOnAVertexOrOnAnEarlierPointSnapAndAreReported) {
  std::vector<TinVertex> shots = Shots(10, 10, 1.0, 3);
  // A stored vertex, a hair away, and a copy of shot 2 a hair away.
  auto stmt = store_->db().Cached(
      "SELECT x, y FROM vertices WHERE abs(x - ?1) < ?2 AND abs(y - ?3) < ?2 LIMIT 1");
  ASSERT_TRUE(stmt.ok());
  (*stmt)->Bind(1, kEditCx).Bind(2, 20 * kEditCell).Bind(3, kEditCy);
  auto row = (*stmt)->Step();
  ASSERT_TRUE(row.ok() && *row);
  const double vx = (*stmt)->ColumnDouble(0), vy = (*stmt)->ColumnDouble(1);
  (*stmt)->Reset();
  shots.push_back({vx + 1e-6 * kEditCell, vy, 500, VertexKind::kUser});
  shots.push_back({shots[2].x, shots[2].y + 1e-5 * kEditCell, 501, VertexKind::kUser});
  auto report = Add(shots);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->inserted, 10);
  ASSERT_EQ(report->snapped.size(), 2u);
  EXPECT_NE(report->snapped[0].find("shots, point 11"), std::string::npos) << report->snapped[0];
  EXPECT_NE(report->snapped[0].find("snapped onto vertex"), std::string::npos);
  EXPECT_NE(report->snapped[1].find("onto shots, point 3"), std::string::npos)
      << report->snapped[1];
  ExpectStoreIntact(*store_, /*full=*/true);
}

TEST_F(MassPoints, BadPointsAreRefusedNamingThePointAndChangeNothing) {
  std::vector<TinVertex> shots = Shots(5, 10, 0.0, 5);
  const auto before = TableChecksums(Path());
  std::vector<TinVertex> outside = shots;
  outside.push_back({kEditCx + 1e7, kEditCy, 500, VertexKind::kUser});
  auto r = Add(outside);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(r.status().message().find("shots, point 6"), std::string::npos) << r.status().message();
  EXPECT_NE(r.status().message().find("lies outside surface 'terrain'"), std::string::npos);
  std::vector<TinVertex> wild = shots;
  wild[1].z = 1e9;
  r = Add(wild);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("shots, point 2: z 1000000000"), std::string::npos)
      << r.status().message();
  wild[1].z = std::nan("");
  r = Add(wild);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("shots, point 2"), std::string::npos);
  EXPECT_EQ(TableChecksums(Path()), before);
}

TEST_F(MassPoints, RemovingTheFeatureTakesEveryPointOut) {
  auto report = Add(Shots(40, 20, 6.0, 13));
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  PointsRemoveOptions o;
  o.feature = report->features_added[0];
  auto removed = RemovePoints(*store_, o);
  ASSERT_TRUE(removed.ok()) << removed.status().ToString();
  EXPECT_EQ(removed->inserted, 40);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM vertices WHERE kind = 'user'"), 0);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM features"), 0);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM changes WHERE action = 'points remove'"), 1);
  ExpectStoreIntact(*store_, /*full=*/true);
}

TEST_F(MassPoints, RemovingABoxKeepsTheRestAsANewFeature) {
  const std::vector<TinVertex> shots = Shots(40, 20, 2.0, 17);
  auto report = Add(shots);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  PointsRemoveOptions o;
  o.surface = "terrain";
  Box box;
  box.Add(Point2{kEditCx - 25 * kEditCell, kEditCy - 25 * kEditCell});
  box.Add(Point2{kEditCx, kEditCy + 25 * kEditCell});
  o.box = box;
  int64_t inside = 0;
  for (const TinVertex& p : shots) inside += box.Contains(Point2{p.x, p.y}) ? 1 : 0;
  ASSERT_GT(inside, 0);
  ASSERT_LT(inside, 40);
  auto removed = RemovePoints(*store_, o);
  ASSERT_TRUE(removed.ok()) << removed.status().ToString();
  EXPECT_EQ(removed->inserted, inside);
  ASSERT_EQ(removed->features_added.size(), 1u);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM vertices WHERE kind = 'user'"), 40 - inside);
  ASSERT_TRUE(ReloadSurface());
  auto rest = LoadFeature(*store_, surface_, removed->features_added[0]);
  ASSERT_TRUE(rest.ok());
  EXPECT_EQ(static_cast<int64_t>(rest->points.size()), 40 - inside);
  ExpectStoreIntact(*store_, /*full=*/true);
}

TEST_F(MassPoints, RemoveRefusesWhatIsNotSurveyPointsAndChangesNothing) {
  auto report = Add(Shots(5, 5, 0.0, 19));
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  const auto before = TableChecksums(Path());
  PointsRemoveOptions none;
  none.surface = "terrain";
  Box far;
  far.Add(Point2{kEditCx + 100 * kEditCell, kEditCy + 100 * kEditCell});
  far.Add(Point2{kEditCx + 101 * kEditCell, kEditCy + 101 * kEditCell});
  none.box = far;
  auto r = RemovePoints(*store_, none);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("no survey points in the box"), std::string::npos);
  PointsRemoveOptions unknown;
  unknown.feature = 999;
  r = RemovePoints(*store_, unknown);
  EXPECT_EQ(r.status().code(), StatusCode::kNotFound);
  PointsRemoveOptions both = none;
  both.feature = report->features_added[0];
  EXPECT_EQ(RemovePoints(*store_, both).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(TableChecksums(Path()), before);
}

}  // namespace
}  // namespace tinbase
