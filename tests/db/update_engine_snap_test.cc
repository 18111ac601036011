// The update engine where new rings meet stored constraints: vertices a hair off an edge snap
// onto it, and rings re-added along earlier crossings stay constrained and locally Delaunay.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "tests/support/update_engine_checks.h"

namespace tinbase {
namespace {

using testing::kCell;
using testing::kCx;
using testing::kCy;
using testing::Ngon;
using testing::PointList;
using testing::UpdateEngineTest;
using testing::WritePolygons;

// Regression (found by the kill -9 test): re-adding a ring whose segment an earlier ring crossed
// made CGAL reroute the new constraint through another vertex (CGAL#6602), leaving an edge
// stored unconstrained and not locally Delaunay.
TEST_F(UpdateEngineTest, RegressionReaddRingAlongEarlierCrossing) {
  std::vector<std::string> files;
  for (int k = 0; k < 6; ++k)
    files.push_back(WritePolygons(dir_, "p" + std::to_string(k) + ".geojson",
                                  {{Ngon(kCx + (k - 3) * 3 * kCell, kCy + (k % 2) * 4 * kCell,
                                         6 * kCell, 20 + k, 0.1 * k)}}));
  for (const std::string& file : files) AddChecked(file, "fill");
  AddChecked(files[0], "fill");
  AddChecked(files[1], "fill");
  AddChecked(files[2], "fill");  // failed the full check before the fix
}

// A ring vertex a hair (0.3 snap distances) beside an earlier ring's constrained edge lands on
// that edge, which is split there for its owner, instead of leaving a sliver beside it.
TEST_F(UpdateEngineTest, PointNearAnExistingConstraintSnapsOntoIt) {
  const PolygonAddReport a =
      AddChecked(WritePolygons(dir_, "a.geojson", {{Ngon(kCx, kCy, 10 * kCell, 12)}}), "fill");
  auto longest = store_->db().Prepare(
      "SELECT c.va, c.vb, p.x, p.y, q.x, q.y FROM constraints c JOIN vertices p ON p.id = c.va "
      "JOIN vertices q ON q.id = c.vb WHERE c.feature = ? "
      "ORDER BY (q.x - p.x) * (q.x - p.x) + (q.y - p.y) * (q.y - p.y) DESC LIMIT 1");
  ASSERT_TRUE(longest.ok());
  Statement* edge = longest->get();
  edge->Bind(1, a.first_feature_id);
  ASSERT_TRUE(*edge->Step());
  const int64_t va = edge->ColumnInt(0), vb = edge->ColumnInt(1);
  const double mx = (edge->ColumnDouble(2) + edge->ColumnDouble(4)) / 2;
  const double my = (edge->ColumnDouble(3) + edge->ColumnDouble(5)) / 2;
  edge->Reset();
  // Outward from a's centre, and along the edge.
  const double ox = (mx - kCx) / std::hypot(mx - kCx, my - kCy);
  const double oy = (my - kCy) / std::hypot(mx - kCx, my - kCy);
  const double px = mx + ox * 0.3 * kSnapCells * kCell, py = my + oy * 0.3 * kSnapCells * kCell;
  const PointList b = {{px, py},
                       {px + 4 * kCell * ox + 2 * kCell * oy, py + 4 * kCell * oy - 2 * kCell * ox},
                       {px + 4 * kCell * ox - 2 * kCell * oy, py + 4 * kCell * oy + 2 * kCell * ox},
                       {px, py}};
  const PolygonAddReport added = AddChecked(WritePolygons(dir_, "b.geojson", {{b}}), "fill");

  EXPECT_EQ(Int("SELECT count(*) FROM constraints WHERE va = " + std::to_string(va) +
                " AND vb = " + std::to_string(vb)),
            0)
      << "the edge the point snapped onto is still whole";
  std::ostringstream on_edge;
  on_edge.precision(17);
  on_edge << "SELECT id FROM vertices WHERE abs(x - " << mx << ") < 1e-6 AND abs(y - " << my
          << ") < 1e-6";
  const int64_t split = Int(on_edge.str());
  ASSERT_GT(split, 0) << "no vertex on the edge where b's vertex was";
  for (int64_t end : {va, vb}) {
    const std::string piece =
        "SELECT count(*) FROM constraints WHERE va = " + std::to_string(std::min(end, split)) +
        " AND vb = " + std::to_string(std::max(end, split));
    EXPECT_EQ(Int(piece + " AND feature = " + std::to_string(a.first_feature_id)), 1);
  }
  EXPECT_GE(Int("SELECT count(*) FROM constraints WHERE feature = " +
                std::to_string(added.first_feature_id) + " AND (va = " + std::to_string(split) +
                " OR vb = " + std::to_string(split) + ")"),
            2);
}

// A polygon whose every vertex lies a hair off an earlier ring's edges (both sides, random
// places along them): each snaps onto its edge; then the earlier ring goes and comes back (its
// new segments pass through those vertices), and both go, every step locally and checked.
TEST_F(UpdateEngineTest, RingOnAnotherRingsEdgesSnapsAndBothGoAgain) {
  const std::string a_file = WritePolygons(dir_, "a.geojson", {{Ngon(kCx, kCy, 10 * kCell, 12)}});
  for (int seed = 1; seed <= 3; ++seed) {
    const PolygonAddReport a = AddChecked(a_file, "fill");
    auto edges = store_->db().Prepare(
        "SELECT c.va, c.vb, p.x, p.y, q.x, q.y FROM constraints c JOIN vertices p ON p.id = c.va "
        "JOIN vertices q ON q.id = c.vb WHERE c.feature = ?");
    ASSERT_TRUE(edges.ok());
    (*edges)->Bind(1, a.first_feature_id);
    struct Near {
      double angle, x, y;
      int64_t va, vb;
    };
    std::vector<Near> points;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> along(0.25, 0.75), off(-0.5, 0.5);
    for (int k = 0; *(*edges)->Step(); ++k) {
      if (k % 2) continue;
      const double px = (*edges)->ColumnDouble(2), py = (*edges)->ColumnDouble(3);
      const double qx = (*edges)->ColumnDouble(4), qy = (*edges)->ColumnDouble(5);
      const double t = along(rng), len = std::hypot(qx - px, qy - py);
      const double o = off(rng) * kSnapCells * kCell;
      const double x = px + t * (qx - px) - o * (qy - py) / len;
      const double y = py + t * (qy - py) + o * (qx - px) / len;
      points.push_back(
          {std::atan2(y - kCy, x - kCx), x, y, (*edges)->ColumnInt(0), (*edges)->ColumnInt(1)});
    }
    (*edges)->Reset();
    ASSERT_GE(points.size(), 4u);
    std::sort(points.begin(), points.end(),
              [](const Near& l, const Near& r) { return l.angle < r.angle; });
    PointList ring;
    for (const Near& p : points) ring.push_back({p.x, p.y});
    ring.push_back(ring.front());
    const PolygonAddReport b =
        AddChecked(WritePolygons(dir_, "b" + std::to_string(seed) + ".geojson", {{ring}}), "erase");
    for (const Near& p : points) {
      EXPECT_EQ(Int("SELECT count(*) FROM constraints WHERE va = " + std::to_string(p.va) +
                    " AND vb = " + std::to_string(p.vb)),
                0)
          << "seed " << seed << ": an edge a vertex snapped onto is still whole";
    }
    RemoveChecked(a.first_feature_id);
    const PolygonAddReport again = AddChecked(a_file, "fill");  // now through b's vertices
    RemoveChecked(b.first_feature_id);
    RemoveChecked(again.first_feature_id);
    EXPECT_EQ(Int("SELECT count(*) FROM constraints"), 0);
    EXPECT_EQ(Int("SELECT count(*) FROM vertices WHERE kind IN ('ring', 'steiner')"), 0);
  }
}

}  // namespace
}  // namespace tinbase
