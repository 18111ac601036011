// RetriangulateUntilSettled on a new ring over a greedy surface of the Hamersley DEM: the patch
// tiles exactly the (grown) conflict region, keeps its outline edge for edge, is locally Delaunay
// across every outline edge, and holds the ring's segments as constraints.
#include "db/edit/local_patch.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "core/geometry/predicates.h"
#include "db/edit/repaint_plan.h"
#include "tests/support/edit_fixture.h"

namespace tinbase {
namespace {

using testing::kEditCell;
using testing::kEditCx;
using testing::kEditCy;
using testing::Ngon;

double Area(const Point2& a, const Point2& b, const Point2& c) {
  return ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)) / 2;
}

class LocalPatchTest : public testing::EditFixture {
 protected:
  // The patch of `edit` and the region it settled on.
  std::pair<LocalPatch, ConflictRegion> Settle(const LocalEdit& edit) {
    const EditContext ctx = Context();
    auto region = FindConflictRegion(ctx, edit);
    EXPECT_TRUE(region.ok()) << region.status().ToString();
    auto plan = PlanRepaint(ctx, edit, region->removed_features);
    EXPECT_TRUE(plan.ok()) << plan.status().ToString();
    const ElevationRules rules(*dems_, dem_, edit.features, region->restore);
    auto patch = RetriangulateUntilSettled(ctx, rules, plan->paint_box, edit.remove, &*region);
    EXPECT_TRUE(patch.ok()) << patch.status().ToString();
    return {std::move(*patch), std::move(*region)};
  }

  Point2 At(int64_t v) {
    auto p = mesh_->At(v);
    EXPECT_TRUE(p.ok());
    return p.ok() ? *p : Point2{};
  }
};

TEST_F(LocalPatchTest, TilesTheRegionAndSettlesItsOutline) {
  const LocalEdit edit = AddRing(Ngon(kEditCx, kEditCy, 6 * kEditCell, 17), 7);
  const auto [patch, region] = Settle(edit);
  ASSERT_GE(patch.rounds, 1);
  ASSERT_EQ(patch.inside.size(), patch.tin.triangles.size());
  const Tin& tin = patch.tin;
  const auto point = [&](uint32_t v) { return Point2{tin.vertices[v].x, tin.vertices[v].y}; };

  // The patch's inside triangles cover exactly R: the same area, every one counter-clockwise.
  double patch_area = 0;
  std::set<std::pair<uint32_t, uint32_t>> directed;
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    if (!patch.inside[t]) continue;
    const auto& v = tin.triangles[t].v;
    ASSERT_GT(Orientation(point(v[0]), point(v[1]), point(v[2])), 0);
    patch_area += Area(point(v[0]), point(v[1]), point(v[2]));
    for (int i = 0; i < 3; ++i) directed.insert({v[i], v[(i + 1) % 3]});
  }
  double region_area = 0;
  for (int64_t t : region.triangles) {
    auto tri = mesh_->Triangle(t);
    ASSERT_TRUE(tri.ok());
    const TriangleRow row = **tri;
    region_area += Area(At(row.v[0]), At(row.v[1]), At(row.v[2]));
  }
  EXPECT_NEAR(patch_area, region_area, 1e-9 * region_area);

  // Every outline edge stays, in R's direction, and the circumcircle of the inside triangle on it
  // does not hold the far corner of the stored triangle across it.
  ASSERT_FALSE(patch.outline.empty());
  for (const OutlineEdge& e : patch.outline) {
    const uint32_t a = patch.local.at(e.a), b = patch.local.at(e.b);
    ASSERT_TRUE(directed.count({a, b})) << "outline edge " << e.a << "-" << e.b << " lost";
    if (!e.outer) continue;
    auto outer = mesh_->Triangle(*e.outer);
    ASSERT_TRUE(outer.ok());
    EXPECT_FALSE(region.Has(*e.outer));
    int64_t far = 0;
    for (int64_t w : (*outer)->v)
      if (w != e.a && w != e.b) far = w;
    for (size_t t = 0; t < tin.triangles.size(); ++t) {
      const auto& v = tin.triangles[t].v;
      if (!patch.inside[t]) continue;
      const bool has =
          (v[0] == a && v[1] == b) || (v[1] == a && v[2] == b) || (v[2] == a && v[0] == b);
      if (!has) continue;
      EXPECT_LE(InCircle(point(v[0]), point(v[1]), point(v[2]), At(far)), 0)
          << "outline edge " << e.a << "-" << e.b << " is not locally Delaunay";
    }
  }

  // The ring's points are vertices of the patch, its segments constrained (through any crossing
  // or vertex on them, none here: every point is new).
  ASSERT_EQ(patch.lines.size(), 1u);
  std::set<std::pair<uint32_t, uint32_t>> constrained;
  for (const auto& [a, b] : tin.constraints) constrained.insert({std::min(a, b), std::max(a, b)});
  const std::vector<uint32_t>& ring = patch.lines[0];
  for (size_t i = 0; i < ring.size(); ++i) {
    const uint32_t a = ring[i], b = ring[(i + 1) % ring.size()];
    EXPECT_EQ(patch.store_ids[a], 0);
    EXPECT_TRUE(constrained.count({std::min(a, b), std::max(a, b)}))
        << "ring segment " << i << " is not a constraint of the patch";
  }
  EXPECT_TRUE(patch.region.Contains({kEditCx + 6 * kEditCell * 0.99, kEditCy}));
}

TEST_F(LocalPatchTest, PaintOnlyEditHasNoPatch) {
  LocalEdit edit;
  edit.changed.Add(Point2{kEditCx, kEditCy});
  edit.changed.Add(Point2{kEditCx + kEditCell, kEditCy + kEditCell});
  const auto [patch, region] = Settle(edit);
  EXPECT_TRUE(region.triangles.empty());
  EXPECT_TRUE(patch.tin.triangles.empty());
  EXPECT_TRUE(patch.outline.empty());
  EXPECT_EQ(patch.rounds, 1);
  EXPECT_GT(patch.grid.geometry.width, 0);  // the DEM under the paint box was read
}

}  // namespace
}  // namespace tinbase
