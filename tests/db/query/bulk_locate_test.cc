// LocatePoints on a stored plane: every answer agrees with a brute-force search and with the
// plane's z, points outside are answered with null in their place, sorted input walks a few steps
// a point, and a sink's error stops the run. The in-memory path answers exactly as the stored one
// (triangle, z to the bit, paint, steps) on random, sorted, on-edge and on-vertex points.
#include "db/query/bulk_locate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "tests/db/query/query_fixture.h"
#include "tests/support/grid_tin.h"
#include "tests/support/store_target.h"
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
    auto stored = testing::StoreSurface(testing::StoreTarget(dir_, "b.tinbase"), "plane",
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

// Both paths on the same points, answer by answer.
class BulkLocatePathsTest : public BulkLocateTest {
 protected:
  void SetUp() override {
    Tin tin = testing::MakeGridTin(40, 40, 5, 1000, 2000, PlaneZ);
    tin.tags = {"sand", "clay"};
    for (size_t t = 0; t < tin.triangles.size(); ++t) {
      if (t % 7 == 0) tin.triangles[t].tag = 0;
      if (t % 11 == 0) tin.triangles[t].tag = 1;
      if (t % 13 == 0) tin.triangles[t].visible = false;
    }
    auto stored = testing::StoreSurface(testing::StoreTarget(dir_, "p.tinbase"), "painted", tin);
    ASSERT_TRUE(stored.ok()) << stored.status().ToString();
    s_ = std::move(*stored);
  }

  std::vector<Answer> RunBy(LocatePath path, const std::vector<Point2>& points) {
    std::vector<Answer> out;
    Status s = LocatePointsBy(path, *s_.store, s_.info, points,
                              [&](size_t i, const Point2& p, const Location* where) {
                                out.push_back({i, p, where ? std::optional(*where) : std::nullopt});
                                return Status::Ok();
                              });
    EXPECT_TRUE(s.ok()) << s.ToString();
    return out;
  }

  // Runs both paths (and the chosen one) and expects the same answers; returns them.
  std::vector<Answer> ExpectSameAnswers(const std::vector<Point2>& points) {
    const auto stored = RunBy(LocatePath::kStored, points);
    const auto memory = RunBy(LocatePath::kInMemory, points);
    const auto chosen = RunBy(LocatePath::kChoose, points);
    EXPECT_EQ(stored.size(), points.size());
    EXPECT_EQ(memory.size(), points.size());
    EXPECT_EQ(chosen.size(), points.size());
    for (size_t i = 0; i < std::min(stored.size(), memory.size()); ++i) {
      const Answer& a = stored[i];
      for (const Answer* b : {&memory[i], &chosen[i]}) {
        const std::string at = "point " + std::to_string(i) + " (" + std::to_string(a.p.x) + ", " +
                               std::to_string(a.p.y) + ")";
        EXPECT_EQ(b->index, i) << at;
        EXPECT_EQ(a.where.has_value(), b->where.has_value()) << at;
        if (!a.where || !b->where) continue;
        EXPECT_EQ(a.where->triangle, b->where->triangle) << at;
        EXPECT_EQ(a.where->z, b->where->z) << at;  // the same formula on the same corners
        EXPECT_EQ(a.where->visible, b->where->visible) << at;
        EXPECT_EQ(a.where->tag, b->where->tag) << at;
        EXPECT_EQ(a.where->steps, b->where->steps) << at;
      }
      if (a.where) {
        EXPECT_TRUE(Holds(s_.loaded, a.where->triangle, a.p));
      }
    }
    return stored;
  }

  static std::vector<Point2> RandomPoints(uint32_t seed, int n) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> ux(990, 1210), uy(1990, 2210);
    std::vector<Point2> points;
    for (int i = 0; i < n; ++i) points.push_back({ux(rng), uy(rng)});
    return points;
  }

  // Every grid vertex, the midpoint of every cell side, and every cell's centre (on its
  // diagonal): each lies on an edge or a vertex, where the triangle is the walk's choice.
  static std::vector<Point2> EdgeAndVertexPoints() {
    std::vector<Point2> points;
    for (int j = 0; j <= 40; ++j) {
      for (int i = 0; i <= 40; ++i) {
        const double x = 1000 + 5 * i, y = 2000 + 5 * j;
        points.push_back({x, y});
        if (i < 40) points.push_back({x + 2.5, y});
        if (j < 40) points.push_back({x, y + 2.5});
        if (i < 40 && j < 40) points.push_back({x + 2.5, y + 2.5});
      }
    }
    return points;
  }
};

TEST_F(BulkLocatePathsTest, RandomPointsInsideAndOutside) {
  const auto answers = ExpectSameAnswers(RandomPoints(11, 4000));
  int outside = 0, tagged = 0, hidden = 0;
  for (const Answer& a : answers) {
    if (!a.where) {
      ++outside;
      continue;
    }
    tagged += a.where->tag.has_value();
    hidden += !a.where->visible;
  }
  // The comparison covered each kind of answer.
  EXPECT_GT(outside, 100);
  EXPECT_GT(tagged, 100);
  EXPECT_GT(hidden, 50);
}

TEST_F(BulkLocatePathsTest, SortedPoints) {
  std::vector<Point2> points = RandomPoints(12, 4000);
  // Row bands of one cell, back and forth: each point near the last, many in the same triangle.
  std::sort(points.begin(), points.end(), [](const Point2& a, const Point2& b) {
    const auto band = [](const Point2& p) { return static_cast<int>(std::floor(p.y / 5)); };
    if (band(a) != band(b)) return band(a) < band(b);
    return band(a) % 2 == 0 ? a.x < b.x : a.x > b.x;
  });
  const auto answers = ExpectSameAnswers(points);
  int held = 0;
  for (const Answer& a : answers) held += a.where && a.where->steps == 0;
  EXPECT_GT(held, 1000) << "points answered by the last triangle";
}

TEST_F(BulkLocatePathsTest, PointsOnEdgesAndVerticesInSeveralOrders) {
  std::vector<Point2> points = EdgeAndVertexPoints();
  ExpectSameAnswers(points);  // row by row: near walks and the last triangle
  std::reverse(points.begin(), points.end());
  ExpectSameAnswers(points);
  std::mt19937 rng(13);
  std::shuffle(points.begin(), points.end(), rng);  // far apart: jumps
  ExpectSameAnswers(points);
  // Mixed with random points, so walks arrive at the same edge from both sides.
  const std::vector<Point2> random = RandomPoints(14, static_cast<int>(points.size()));
  std::vector<Point2> mixed;
  for (size_t i = 0; i < points.size(); ++i) {
    mixed.push_back(random[i]);
    mixed.push_back(points[i]);
  }
  ExpectSameAnswers(mixed);
}

TEST_F(BulkLocatePathsTest, ALargeRequestAgainstTheSurfaceIsLocatedInMemory) {
  const auto triangles = static_cast<size_t>(40 * 40 * 2);
  const size_t fewest = triangles / kLoadTrianglesPerPoint;
  auto path = ChooseLocatePath(*s_.store, s_.info, fewest);
  ASSERT_TRUE(path.ok()) << path.status().ToString();
  EXPECT_EQ(*path, LocatePath::kInMemory);
  path = ChooseLocatePath(*s_.store, s_.info, fewest - 1);
  ASSERT_TRUE(path.ok()) << path.status().ToString();
  EXPECT_EQ(*path, LocatePath::kStored);
  path = ChooseLocatePath(*s_.store, s_.info, 1);
  ASSERT_TRUE(path.ok()) << path.status().ToString();
  EXPECT_EQ(*path, LocatePath::kStored);
}

// A link to a triangle that does not exist: the stored walk reports Corruption when it reaches
// it, so the in-memory path, which cannot hold such rows by position, leaves the run to the
// stored walk, and both end alike.
TEST_F(BulkLocatePathsTest, ABrokenLinkEndsBothPathsAlike) {
  ASSERT_TRUE(s_.store->db().Exec("UPDATE triangles SET n0 = 999999 WHERE n0 IS NULL").ok());
  const std::vector<Point2> points = RandomPoints(15, 500);
  std::vector<std::vector<Answer>> answers(2);
  std::vector<Status> status;
  for (LocatePath path : {LocatePath::kStored, LocatePath::kInMemory}) {
    auto& out = answers[status.size()];
    status.push_back(LocatePointsBy(
        path, *s_.store, s_.info, points, [&](size_t i, const Point2& p, const Location* where) {
          out.push_back({i, p, where ? std::optional(*where) : std::nullopt});
          return Status::Ok();
        }));
  }
  EXPECT_EQ(status[0].code(), StatusCode::kCorruption) << status[0].ToString();
  EXPECT_EQ(status[1].ToString(), status[0].ToString());
  ASSERT_EQ(answers[1].size(), answers[0].size());
  for (size_t i = 0; i < answers[0].size(); ++i)
    EXPECT_EQ(answers[1][i].where.has_value(), answers[0][i].where.has_value()) << i;
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
