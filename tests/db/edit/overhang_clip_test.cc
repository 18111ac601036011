// Polygons that overhang the surface's data area (db/edit/overhang_clip.h, core/vector/
// data_area_clip.h): the clip geometry on hand-made areas, then real maps larger than their DEM.
// The Hamersley geology (61 units) goes over the western half of its DEM, cut as a sheet; the
// Luxembourg cantons over the country's DEM, nodata outside the border. Each write ends with the
// full check; clipped rings must drape (a finite DEM elevation at every stored vertex), and what
// is stored plus what was cut must make up the polygon as read.
#include "db/edit/overhang_clip.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "core/raster/gdal_raster.h"
#include "core/vector/polygon_source.h"
#include "db/dem_store.h"
#include "db/feature_store.h"
#include "db/polygon_editor.h"
#include "db/surface_builder.h"
#include "db/surface_store.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::TempDir;

Ring Rect(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

double AreaOf(const std::vector<Polygon>& polygons) {
  double area = 0;
  for (const Polygon& p : polygons) {
    area += std::fabs(SignedDoubleArea(p.shell)) / 2;
    for (const Ring& hole : p.holes) area -= std::fabs(SignedDoubleArea(hole)) / 2;
  }
  return area;
}

DataArea TenByTen() {
  DataArea area;
  area.hull = {0, 0, 10, 10};
  area.hull_inset = 1e-9;
  return area;
}

TEST(DataAreaClipTest, InsideComesBackBitForBit) {
  const std::vector<Polygon> in = {{Rect(1, 1, 9, 9), {}}};
  auto clip = ClipToDataArea(in, TenByTen());
  ASSERT_TRUE(clip.ok()) << clip.status().ToString();
  EXPECT_EQ(clip->verdict, ClipVerdict::kInside);
  ASSERT_EQ(clip->polygons.size(), 1u);
  ASSERT_EQ(clip->polygons[0].shell.size(), in[0].shell.size());
  for (size_t k = 0; k < in[0].shell.size(); ++k)
    EXPECT_TRUE(SamePoint(clip->polygons[0].shell[k], in[0].shell[k])) << k;
  EXPECT_EQ(clip->area_outside, 0);
}

TEST(DataAreaClipTest, OverhangIsCutAndMeasured) {
  auto clip = ClipToDataArea({{Rect(5, 2, 15, 8), {}}}, TenByTen());
  ASSERT_TRUE(clip.ok()) << clip.status().ToString();
  EXPECT_EQ(clip->verdict, ClipVerdict::kCut);
  EXPECT_NEAR(clip->area_outside, 30, 1e-6);
  EXPECT_NEAR(AreaOf(clip->polygons), 30, 1e-6);
  for (const Polygon& p : clip->polygons) {
    EXPECT_GT(SignedDoubleArea(p.shell), 0) << "shell counter-clockwise";
    for (const Point2& v : p.shell) EXPECT_LT(v.x, 10) << FormatPoint(v) << " on the hull's edge";
  }
}

TEST(DataAreaClipTest, WhollyOutsideIsOutside) {
  auto clip = ClipToDataArea({{Rect(20, 20, 30, 30), {}}}, TenByTen());
  ASSERT_TRUE(clip.ok()) << clip.status().ToString();
  EXPECT_EQ(clip->verdict, ClipVerdict::kOutside);
  EXPECT_TRUE(clip->polygons.empty());
  EXPECT_NEAR(clip->area_outside, 100, 1e-9);
}

TEST(DataAreaClipTest, NodataBecomesAHole) {
  DataArea area = TenByTen();
  area.nodata = {{4, 4, 6, 6}};
  auto clip = ClipToDataArea({{Rect(2, 2, 8, 8), {}}}, area);
  ASSERT_TRUE(clip.ok()) << clip.status().ToString();
  EXPECT_EQ(clip->verdict, ClipVerdict::kCut);
  ASSERT_EQ(clip->polygons.size(), 1u);
  EXPECT_EQ(clip->polygons[0].holes.size(), 1u);
  EXPECT_NEAR(clip->area_outside, 4, 1e-6);
}

TEST(DataAreaClipTest, SquaresWithoutElevationNeedFourNodataCells) {
  // 4 x 3 cells of 1, origin (0, 3), north up; N = nodata:
  //   N N N 1
  //   N N 1 1
  //   N N 1 1
  constexpr float n = std::numeric_limits<float>::quiet_NaN();
  Grid grid;
  grid.geometry.origin_x = 0;
  grid.geometry.origin_y = 3;
  grid.geometry.cell_x = 1;
  grid.geometry.cell_y = -1;
  grid.geometry.width = 4;
  grid.geometry.height = 3;
  grid.cells = {n, n, n, 1, n, n, 1, 1, n, n, 1, 1};
  const std::vector<PlanRect> rects = NoElevationRectangles(grid);
  // The square between the centres of columns 0-1 and rows 0-2 (one rectangle, two rows merged);
  // column 1-2 squares have a valid cell and are not blank.
  ASSERT_EQ(rects.size(), 1u);
  EXPECT_EQ(rects[0].min_x, 0.5);
  EXPECT_EQ(rects[0].max_x, 1.5);
  EXPECT_EQ(rects[0].min_y, 0.5);
  EXPECT_EQ(rects[0].max_y, 2.5);
}

// A store with one DEM and surface "terrain" (greedy, 5 m).
class OverhangTest : public ::testing::Test {
 protected:
  void Open(const std::string& dem_file) {
    path_ = testing::StoreTarget(dir_, "s.tinbase");
    auto store = Store::Create(path_, "");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    DemStore dems(*store_);
    auto imported = dems.Import({dem_file}, {});
    ASSERT_TRUE(imported.ok()) << imported.status().ToString();
    dem_ = imported->dem;
    SurfaceBuildOptions o;
    o.surface = "terrain";
    o.greedy.tolerance = 5;
    auto built = BuildSurfaceFromDem(*store_, o);
    ASSERT_TRUE(built.ok()) << built.status().ToString();
  }

  // The western `columns` of the Hamersley DEM as a sheet of its own.
  std::string WestSheet(int64_t columns) {
    auto raster = GdalRaster::Open(DataPath("geology/hamersley/dtm_rp.tif"));
    EXPECT_TRUE(raster.ok()) << raster.status().ToString();
    auto full = raster->Read();
    EXPECT_TRUE(full.ok()) << full.status().ToString();
    Grid west = *full;
    west.geometry.width = columns;
    west.cells.clear();
    for (int64_t r = 0; r < full->geometry.height; ++r)
      for (int64_t c = 0; c < columns; ++c) west.cells.push_back(full->At(c, r));
    const std::string path = dir_.Path("west.tif");
    EXPECT_TRUE(WriteGeoTiff(west, path).ok());
    return path;
  }

  PolygonAddOptions Options(const std::string& file, const std::string& tag_field) {
    PolygonAddOptions o;
    o.surface = "terrain";
    o.file = file;
    o.mode = FeatureMode::kFill;
    o.tag_field = tag_field;
    return o;
  }

  // The features of `file` as read into the store's CRS, by label.
  std::map<std::string, std::vector<Polygon>> ReadByLabel(const std::string& file) {
    VectorSourceOptions source;
    auto crs = store_->GetCrs();
    EXPECT_TRUE(crs.ok() && *crs);
    source.target_crs = **crs;
    auto read = ReadPolygonFeatures(file, source);
    EXPECT_TRUE(read.ok()) << read.status().ToString();
    std::map<std::string, std::vector<Polygon>> out;
    for (const PolygonFeature& f : *read) out[f.label] = f.polygons;
    return out;
  }

  // Every clipped feature: stored inside the hull, draped on data (finite elevation at every
  // ring vertex), and its stored area plus the area cut is the area read.
  void ExpectCutsAddUp(const PolygonAddReport& report, const std::string& file) {
    auto surface = SurfaceStore(*store_).Find("terrain");
    ASSERT_TRUE(surface.ok());
    const auto read = ReadByLabel(file);
    DemStore dems(*store_);
    const GridGeometry& g = dem_.geometry;
    for (const OverhangCut& cut : report.clipped) {
      auto stored = LoadFeature(*store_, *surface, cut.feature);
      ASSERT_TRUE(stored.ok()) << stored.status().ToString();
      ASSERT_TRUE(read.count(cut.label)) << cut.label;
      EXPECT_GT(cut.area_outside, 0) << cut.label;
      const double in = AreaOf(read.at(cut.label));
      EXPECT_NEAR(AreaOf(stored->polygons) + cut.area_outside, in, 1e-6 * in) << cut.label;
      for (const Polygon& p : stored->polygons) {
        for (const Point2& v : p.shell) {
          EXPECT_GT(v.x, g.CellCenterX(0)) << cut.label << " " << FormatPoint(v);
          EXPECT_LT(v.x, g.CellCenterX(g.width - 1)) << cut.label << " " << FormatPoint(v);
          auto z = dems.Elevation(dem_, v.x, v.y);
          ASSERT_TRUE(z.ok());
          EXPECT_TRUE(std::isfinite(*z)) << cut.label << " " << FormatPoint(v) << " has no data";
        }
      }
    }
  }

  TempDir dir_;
  std::string path_;
  std::unique_ptr<Store> store_;
  DemInfo dem_;
};

constexpr char kGeology[] = "geology/hamersley/geology.geojson";

TEST_F(OverhangTest, GeologyOverOneSheetAddsThePartsOnIt) {
  Open(WestSheet(100));
  PolygonAddOptions o = Options(DataPath(kGeology), "unitname");
  o.each = true;
  auto report = AddPolygons(*store_, o);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_TRUE(report->failures.empty()) << report->failures.front();
  EXPECT_GT(report->clipped.size(), 5u);
  EXPECT_GT(report->skipped.size(), 5u);
  EXPECT_EQ(report->features + static_cast<int64_t>(report->skipped.size()), 61);
  for (const std::string& s : report->skipped)
    EXPECT_NE(s.find(": lies wholly outside the data area of surface 'terrain'"), std::string::npos)
        << s;
  testing::ExpectStoreIntact(*store_, /*full=*/true);
  ExpectCutsAddUp(*report, DataPath(kGeology));
}

TEST_F(OverhangTest, WhollyOutsideIsAnErrorWithoutEach) {
  Open(WestSheet(100));
  store_.reset();
  const auto before = testing::TableChecksums(path_);
  auto store = Store::Open(path_);
  ASSERT_TRUE(store.ok());
  store_ = std::move(*store);
  auto report = AddPolygons(*store_, Options(DataPath(kGeology), "unitname"));
  ASSERT_EQ(report.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(report.status().message().find("lies wholly outside the data area"), std::string::npos)
      << report.status().message();
  store_.reset();
  EXPECT_EQ(testing::TableChecksums(path_), before);
}

TEST_F(OverhangTest, StrictRefusesAsBefore) {
  Open(WestSheet(100));
  PolygonAddOptions o = Options(DataPath(kGeology), "unitname");
  o.each = true;
  o.strict = true;
  auto report = AddPolygons(*store_, o);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_TRUE(report->clipped.empty());
  EXPECT_TRUE(report->skipped.empty());
  ASSERT_FALSE(report->failures.empty());
  for (const std::string& f : report->failures)
    EXPECT_TRUE(f.find("lies outside surface 'terrain'") != std::string::npos ||
                f.find("no elevation") != std::string::npos)
        << f;
  testing::ExpectStoreIntact(*store_, /*full=*/true);
}

TEST_F(OverhangTest, CantonsAreCutAtTheBorderNodata) {
  Open(DataPath("dem/elev.tif"));
  const std::string cantons = DataPath("vector/lux/lux.shp");
  auto report = AddPolygons(*store_, Options(cantons, "NAME_2"));
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->features, 12);
  EXPECT_FALSE(report->clipped.empty());
  testing::ExpectStoreIntact(*store_, /*full=*/true);
  ExpectCutsAddUp(*report, cantons);
}

TEST_F(OverhangTest, UpdateClipsToo) {
  Open(WestSheet(100));
  // A canton-sized square across the sheet's eastern edge.
  const GridGeometry& g = dem_.geometry;
  const double east = g.CellCenterX(g.width - 1), y = (g.MinY() + g.MaxY()) / 2;
  const double d = 10 * g.cell_x;
  const std::string inside = dir_.Path("in.geojson"), across = dir_.Path("across.geojson");
  const auto write = [](const std::string& path, double x0, double y0, double x1, double y1) {
    FILE* f = std::fopen(path.c_str(), "w");
    std::fprintf(f,
                 R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": )"
                 R"({"name": "urn:ogc:def:crs:EPSG::28350"}}, "features": [{"type": "Feature", )"
                 R"("properties": {}, "geometry": {"type": "Polygon", "coordinates": )"
                 R"([[[%.17g, %.17g], [%.17g, %.17g], [%.17g, %.17g], [%.17g, %.17g], )"
                 R"([%.17g, %.17g]]]}}]})",
                 x0, y0, x1, y0, x1, y1, x0, y1, x0, y0);
    std::fclose(f);
  };
  write(inside, east - 3 * d, y - d, east - d, y + d);
  write(across, east - d, y - d, east + d, y + d);
  PolygonAddOptions o = Options(inside, "");
  o.tag = "square";
  auto added = AddPolygons(*store_, o);
  ASSERT_TRUE(added.ok()) << added.status().ToString();
  EXPECT_TRUE(added->clipped.empty());
  o.file = across;
  auto updated = UpdatePolygon(*store_, added->first_feature_id, o);
  ASSERT_TRUE(updated.ok()) << updated.status().ToString();
  ASSERT_EQ(updated->clipped.size(), 1u);
  EXPECT_NEAR(updated->clipped[0].area_outside, 2 * d * (east + d - east), 1e-6 * d * d);
  testing::ExpectStoreIntact(*store_, /*full=*/true);
}

}  // namespace
}  // namespace tinbase
