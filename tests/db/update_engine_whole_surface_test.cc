// Edits whose conflict region is most of the surface: the engine re-triangulates it whole
// (kMinWholeSurfaceRegion), equal in paint to the same load feature by feature, and rolls back
// cleanly from a failure at any write step.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "db/point_locator.h"
#include "tests/support/update_engine_checks.h"

namespace tinbase {
namespace {

using testing::kCell;
using testing::kCx;
using testing::kCy;
using testing::kMapSide;
using testing::kMapSurface;
using testing::kMapUnitCells;
using testing::Ngon;
using testing::PointList;
using testing::StoreTarget;
using testing::UpdateEngineTest;
using testing::WritePolygons;

// A map of side x side square units tiling most of the DEM (rings through a point every DEM
// cell, so their segments touch most triangles): loaded in one transaction, its conflict region
// is more than half of the surface, which the engine then re-triangulates whole
// (kMinWholeSurfaceRegion).
std::vector<std::vector<PointList>> SquareMap(int side, double cells_per_unit) {
  const double unit = cells_per_unit * kCell;
  const double x0 = kCx - side * unit / 2 + 0.37 * kCell, y0 = kCy - side * unit / 2 + 0.21 * kCell;
  const int steps = static_cast<int>(cells_per_unit);
  std::vector<std::vector<PointList>> map;
  for (int j = 0; j < side; ++j) {
    for (int i = 0; i < side; ++i) {
      const double x = x0 + i * unit, y = y0 + j * unit;
      PointList ring;
      for (int k = 0; k < steps; ++k) ring.push_back({x + unit * k / steps, y});
      for (int k = 0; k < steps; ++k) ring.push_back({x + unit, y + unit * k / steps});
      for (int k = 0; k < steps; ++k) ring.push_back({x + unit * (steps - k) / steps, y + unit});
      for (int k = 0; k < steps; ++k) ring.push_back({x, y + unit * (steps - k) / steps});
      ring.push_back(ring.front());
      map.push_back({ring});
    }
  }
  return map;
}

// Visibility and tag at points of a grid over the map, none on a ring: what paint a user sees,
// equal for any two triangulations of the same constraints whose paint is right.
std::vector<std::string> PaintSamples(Store& store) {
  auto surface = SurfaceStore(store).Find(kMapSurface);
  EXPECT_TRUE(surface.ok());
  std::vector<std::string> samples;
  if (!surface.ok()) return samples;
  PointLocator locator(store, *surface);
  const double half = kMapSide * kMapUnitCells * kCell / 2;
  for (double y = kCy - half; y < kCy + half; y += 2.9 * kCell) {
    for (double x = kCx - half; x < kCx + half; x += 3.1 * kCell) {
      auto at = locator.Locate(x, y);
      EXPECT_TRUE(at.ok()) << at.status().ToString();
      if (!at.ok()) continue;
      samples.push_back(std::to_string(at->visible) + ":" + at->tag.value_or("-"));
    }
  }
  return samples;
}

TEST_F(UpdateEngineTest, ManyFeaturesOverMostOfTheSurfaceReplaceItWhole) {
  const std::string file = WritePolygons(dir_, "map.geojson", SquareMap(kMapSide, kMapUnitCells));
  const std::string surface = std::to_string(BuildMapSurface());
  const int64_t triangles_before = Int("SELECT count(*) FROM triangles WHERE surface = " + surface);
  const int64_t last_id_before = Int("SELECT max(id) FROM triangles");
  const auto vertices_before = VertexRows();
  const auto terrain_before = Rows();  // both surfaces' rows
  // The same load feature by feature, every edit local, in a copy of the store.
  store_.reset();
  std::filesystem::copy_file(StoreTarget(dir_, "s.tinbase"), StoreTarget(dir_, "each.tinbase"));
  Reopen();

  PolygonAddOptions o;
  o.surface = kMapSurface;
  o.file = file;
  o.mode = FeatureMode::kFill;
  o.tag_field = "unit";
  auto report = AddPolygons(*store_, o);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  testing::ExpectStoreIntact(*store_, /*full=*/true);
  EXPECT_EQ(report->features, kMapSide * kMapSide);
  // The other surface's triangles are as they were.
  const auto after = Rows();
  for (const auto& [id, row] : terrain_before) {
    if (Int("SELECT count(*) FROM triangles WHERE surface = 1 AND id = " + std::to_string(id))) {
      EXPECT_TRUE(after.count(id) && after.at(id) == row) << "terrain triangle " << id;
    }
  }
  // Every triangle was replaced, by rows with ids above the old ones.
  EXPECT_EQ(report->removed, triangles_before);
  EXPECT_EQ(report->added, Int("SELECT count(*) FROM triangles WHERE surface = " + surface));
  EXPECT_EQ(Int("SELECT count(*) FROM triangles WHERE surface = " + surface +
                " AND id <= " + std::to_string(last_id_before)),
            0);
  // Vertices that stay keep their ids and rows (a fill moves none and drops none).
  EXPECT_EQ(VertexRows(vertices_before.size()), vertices_before);
  auto changes = ChangesSince(*store_, report->tx - 1);
  ASSERT_TRUE(changes.ok());
  ASSERT_EQ(changes->size(), 1u);
  EXPECT_EQ((*changes)[0].removed, report->removed);
  EXPECT_EQ((*changes)[0].added, report->added);
  EXPECT_EQ(Int("SELECT count(*) FROM features WHERE attributes LIKE '%\"unit\"%'"),
            kMapSide * kMapSide);
  const std::vector<std::string> whole = PaintSamples(*store_);

  auto each_store = Store::Open(StoreTarget(dir_, "each.tinbase"));
  ASSERT_TRUE(each_store.ok());
  o.each = true;
  auto each = AddPolygons(**each_store, o);
  ASSERT_TRUE(each.ok()) << each.status().ToString();
  EXPECT_TRUE(each->failures.empty());
  EXPECT_LT(each->removed, triangles_before * static_cast<int64_t>(kMapSide) * kMapSide / 4)
      << "feature by feature, each edit stays local";
  testing::ExpectStoreIntact(**each_store, /*full=*/true);
  EXPECT_EQ(PaintSamples(**each_store), whole);
}

// As FailureAtEveryWriteStepRollsBack, for the whole-surface path.
TEST_F(UpdateEngineTest, FailureAtEveryWriteStepOfAWholeSurfaceEditRollsBack) {
  const std::string file = WritePolygons(dir_, "map.geojson", SquareMap(kMapSide, kMapUnitCells));
  const std::string surface = std::to_string(BuildMapSurface());
  const int64_t triangles_before = Int("SELECT count(*) FROM triangles WHERE surface = " + surface);
  PolygonAddOptions o;
  o.surface = kMapSurface;
  o.file = file;
  o.mode = FeatureMode::kFill;
  o.tag_field = "unit";
  EXPECT_EQ(FailEachWriteStepUntilItSucceeds(o).removed, triangles_before)
      << "not the whole-surface path";
}

}  // namespace
}  // namespace tinbase
