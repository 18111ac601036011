// The update engine next to nodata: polygons near and around DEM cells without data keep every
// invariant, and the triangles over nodata stay hidden.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/raster/gdal_raster.h"
#include "tests/support/update_engine_checks.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::Ngon;
using testing::StoreTarget;
using testing::TempDir;
using testing::WritePolygons;

// Luxembourg: a warped geographic DEM with nodata all around the country; R meets nodata
// triangles, which must stay hidden.
TEST(UpdateEngineNodataTest, PolygonsNearNodataKeepEveryInvariant) {
  TempDir dir;
  auto store = Store::Create(StoreTarget(dir, "lux.tinbase"), "");
  ASSERT_TRUE(store.ok());
  DemStore dems(**store);
  auto imported = dems.Import({DataPath("dem/elev.tif")}, {});
  ASSERT_TRUE(imported.ok()) << imported.status().ToString();
  SurfaceBuildOptions o;
  o.surface = "terrain";
  o.greedy.tolerance = 5;
  ASSERT_TRUE(BuildSurfaceFromDem(**store, o).ok());
  const GridGeometry& g = imported->dem.geometry;
  const double cx = (g.MinX() + g.MaxX()) / 2, cy = (g.MinY() + g.MaxY()) / 2;
  auto crs = (*store)->GetCrs();
  ASSERT_TRUE(crs.ok() && crs->has_value());
  auto epsg = (*crs)->Epsg();
  ASSERT_TRUE(epsg.has_value());
  for (int k = 0; k < 3; ++k) {
    PolygonAddOptions add;
    add.surface = "terrain";
    add.mode = k == 1 ? FeatureMode::kErase : FeatureMode::kFill;
    add.tag = "unit" + std::to_string(k);
    add.file = WritePolygons(
        dir, "p" + std::to_string(k) + ".geojson",
        {{Ngon(cx + (k - 1) * 5 * g.cell_x, cy, 10 * g.cell_x, 18 + k, 0.2 * k)}}, *epsg);
    auto added = AddPolygons(**store, add);
    ASSERT_TRUE(added.ok()) << added.status().ToString();
    testing::ExpectStoreIntact(**store, /*full=*/true);
  }
}

// A fill around a hole of nodata in a synthetic DEM: the blocks over the hole are painted
// triangle by triangle (their triangles stay hidden), the others on data whole.
TEST(UpdateEngineNodataTest, LargeFillAroundANodataHole) {
  TempDir dir;
  Grid grid;
  grid.geometry = GridGeometry{500000, 5200000, 10, -10, 120, 120};
  auto crs = Crs::FromUserInput("EPSG:32632");
  ASSERT_TRUE(crs.ok());
  grid.crs_wkt = crs->Wkt();
  grid.cells.resize(120 * 120);
  for (int64_t r = 0; r < 120; ++r)
    for (int64_t c = 0; c < 120; ++c)
      grid.cells[static_cast<size_t>(r * 120 + c)] =
          std::abs(r - 60) < 8 && std::abs(c - 55) < 6
              ? std::numeric_limits<float>::quiet_NaN()
              : static_cast<float>(300 + 20 * std::sin(c * 0.05) * std::cos(r * 0.04));
  ASSERT_TRUE(WriteGeoTiff(grid, dir.Path("hole.tif")).ok());
  auto store = Store::Create(StoreTarget(dir, "hole.tinbase"), "");
  ASSERT_TRUE(store.ok());
  DemStore dems(**store);
  ASSERT_TRUE(dems.Import({dir.Path("hole.tif")}, {}).ok());
  SurfaceBuildOptions o;
  o.surface = "terrain";
  o.greedy.tolerance = 0.5;
  ASSERT_TRUE(BuildSurfaceFromDem(**store, o).ok());
  const auto hidden = [&] {
    return *(*store)->db().QueryInt("SELECT count(*) FROM triangles WHERE visible = 0");
  };
  ASSERT_GT(hidden(), 0);
  PolygonAddOptions big;
  big.surface = "terrain";
  big.mode = FeatureMode::kFill;
  big.tag = "big";
  big.file = WritePolygons(dir, "big.geojson", {{Ngon(500600, 5199400, 500, 48)}}, 32632);
  auto added = AddPolygons(**store, big);
  ASSERT_TRUE(added.ok()) << added.status().ToString();
  testing::ExpectStoreIntact(**store, /*full=*/true);
  EXPECT_GT(hidden(), 0);
  EXPECT_GT(*(*store)->db().QueryInt("SELECT count(*) FROM triangles WHERE tag IS NOT NULL"),
            *(*store)->db().QueryInt("SELECT count(*) FROM triangles") / 4);
  auto removed = RemovePolygon(**store, added->first_feature_id);
  ASSERT_TRUE(removed.ok()) << removed.status().ToString();
  testing::ExpectStoreIntact(**store, /*full=*/true);
  EXPECT_EQ(*(*store)->db().QueryInt("SELECT count(*) FROM triangles WHERE tag IS NOT NULL"), 0);
}

}  // namespace
}  // namespace tinbase
