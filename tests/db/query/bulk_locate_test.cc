// LocatePoints on a stored plane: every answer agrees with a brute-force search and with the
// plane's z, points outside are answered with null in their place, sorted input walks a few steps
// a point, and a sink's error stops the run.
#include "db/query/bulk_locate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "tests/db/query/query_fixture.h"
#include "tests/support/grid_tin.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::PlaneZ;
using testing::TempDir;

bool Holds(const LoadedSurface& s, int64_t triangle_id, const Point2& p) {
  auto it = std::lower_bound(s.triangle_ids.begin(), s.triangle_ids.end(), triangle_id);
  if (it == s.triangle_ids.end() || *it != triangle_id) return false;
  const auto& v = s.tin.triangles[static_cast<size_t>(it - s.triangle_ids.begin())].v;
  for (int i = 0; i < 3; ++i) {
    const TinVertex& a = s.tin.vertices[v[(i + 1) % 3]];
    const TinVertex& b = s.tin.vertices[v[(i + 2) % 3]];
    if (Orientation({a.x, a.y}, {b.x, b.y}, p) < 0) return false;
  }
  return true;
}

class BulkLocateTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto stored = testing::StoreSurface(dir_.Path("b.tinbase"), "plane",
                                        testing::MakeGridTin(40, 40, 5, 1000, 2000, PlaneZ));
    ASSERT_TRUE(stored.ok()) << stored.status().ToString();
    s_ = std::move(*stored);
  }

  struct Answer {
    size_t index;
    Point2 p;
    std::optional<Location> where;
  };
  std::vector<Answer> Run(const std::vector<Point2>& points) {
    std::vector<Answer> out;
    Status s = LocatePoints(*s_.store, s_.info, points,
                            [&](size_t i, const Point2& p, const Location* where) {
                              out.push_back({i, p, where ? std::optional(*where) : std::nullopt});
                              return Status::Ok();
                            });
    EXPECT_TRUE(s.ok()) << s.ToString();
    return out;
  }

  TempDir dir_;
  testing::StoredSurface s_;
};

TEST_F(BulkLocateTest, RandomPointsInsideAndOutsideAgreeWithBruteForceInOrder) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(990, 1210), uy(1990, 2210);
  std::vector<Point2> points;
  for (int i = 0; i < 3000; ++i) points.push_back({ux(rng), uy(rng)});
  points.push_back({1000, 2000});  // a corner vertex
  points.push_back({1100, 2100});  // an inner vertex
  const auto answers = Run(points);
  ASSERT_EQ(answers.size(), points.size());
  int outside = 0;
  double steps = 0;
  for (size_t i = 0; i < answers.size(); ++i) {
    const Answer& a = answers[i];
    EXPECT_EQ(a.index, i);
    EXPECT_EQ(a.p.x, points[i].x);
    const bool inside = a.p.x >= 1000 && a.p.x <= 1200 && a.p.y >= 2000 && a.p.y <= 2200;
    ASSERT_EQ(a.where.has_value(), inside) << a.p.x << " " << a.p.y;
    if (!inside) {
      ++outside;
      continue;
    }
    EXPECT_TRUE(Holds(s_.loaded, a.where->triangle, a.p)) << a.p.x << " " << a.p.y;
    EXPECT_NEAR(a.where->z, PlaneZ(a.p.x, a.p.y), 1e-9);
    EXPECT_TRUE(a.where->visible);
    steps += a.where->steps;
  }
  EXPECT_GT(outside, 100);
  // A point far from the last one jumps to its block instead of walking across the grid from
  // the last answer (about 45 steps on average here, against about 8).
  EXPECT_LT(steps / static_cast<double>(answers.size() - outside), 12.0) << "mean steps";
}

TEST_F(BulkLocateTest, SortedPointsWalkAFewStepsEach) {
  std::vector<Point2> points;
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i) {
      const int col = j % 2 == 0 ? i : 39 - i;  // back and forth, each point near the last
      points.push_back({1002.5 + 5 * col, 2002.5 + 5 * j});
    }
  const auto answers = Run(points);
  ASSERT_EQ(answers.size(), points.size());
  double steps = 0;
  for (const Answer& a : answers) {
    ASSERT_TRUE(a.where.has_value());
    EXPECT_NEAR(a.where->z, PlaneZ(a.p.x, a.p.y), 1e-9);
    steps += a.where->steps;
  }
  // Neighbouring cells are two or three triangles apart.
  EXPECT_LT(steps / static_cast<double>(answers.size()), 4.0);
}

TEST_F(BulkLocateTest, ASinkErrorStopsTheRun) {
  std::vector<Point2> points(20, Point2{1100, 2100});
  int calls = 0;
  Status s =
      LocatePoints(*s_.store, s_.info, points, [&](size_t i, const Point2&, const Location*) {
        ++calls;
        return i == 5 ? Status::IOError("stdout closed") : Status::Ok();
      });
  EXPECT_EQ(s.code(), StatusCode::kIOError);
  EXPECT_EQ(calls, 6);
}

}  // namespace
}  // namespace tinbase
