// Feature rows and the per-feature surface (`tinbase export --feature`): the inside of a polygon
// with a hole, cut out of a surface it was inserted into, covers exactly the polygon's area.
#include "db/feature_store.h"

#include <gtest/gtest.h>

#include "db/dem_store.h"
#include "db/polygon_editor.h"
#include "db/surface_builder.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::Ngon;
using testing::StoreTarget;
using testing::TempDir;

double RingArea(const testing::PointList& ring) {
  double twice = 0;
  for (size_t i = 0; i + 1 < ring.size(); ++i)
    twice += ring[i].first * ring[i + 1].second - ring[i + 1].first * ring[i].second;
  return std::fabs(twice) / 2;
}

TEST(FeatureStoreTest, FeatureSurfaceIsTheInsideWithoutTheHole) {
  TempDir dir;
  auto store = Store::Create(StoreTarget(dir, "s.tinbase"), "");
  ASSERT_TRUE(store.ok());
  DemStore dems(**store);
  ASSERT_TRUE(dems.Import({testing::DataPath("geology/hamersley/dtm_rp.tif")}, {}).ok());
  SurfaceBuildOptions build;
  build.surface = "terrain";
  build.greedy.tolerance = 5;
  ASSERT_TRUE(BuildSurfaceFromDem(**store, build).ok());
  const double cx = 539300, cy = 7497340, cell = 344.404386931320971;
  const auto shell = Ngon(cx, cy, 9 * cell, 24), hole = Ngon(cx + cell, cy, 3 * cell, 9, 0.4);
  PolygonAddOptions o;
  o.surface = "terrain";
  o.file = testing::WritePolygons(dir, "p.geojson", {{shell, hole}});
  o.mode = FeatureMode::kFill;
  o.tag = "granite";
  auto added = AddPolygons(**store, o);
  ASSERT_TRUE(added.ok()) << added.status().ToString();

  auto cut = LoadFeatureSurface(**store, added->first_feature_id);
  ASSERT_TRUE(cut.ok()) << cut.status().ToString();
  double area = 0;
  for (const TinTriangle& t : cut->tin.triangles) {
    const TinVertex &a = cut->tin.vertices[t.v[0]], &b = cut->tin.vertices[t.v[1]],
                    &c = cut->tin.vertices[t.v[2]];
    area += ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)) / 2;
    ASSERT_NE(t.tag, kNoTag);
    EXPECT_EQ(cut->tin.tags[t.tag], "granite");
  }
  const double expected = RingArea(shell) - RingArea(hole);
  EXPECT_NEAR(area, expected, 1e-6 * expected);
  EXPECT_EQ(cut->triangle_ids.size(), cut->tin.triangles.size());

  EXPECT_EQ(LoadFeatureSurface(**store, 999).status().code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace tinbase
