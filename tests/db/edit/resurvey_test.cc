// `dem import --update-surfaces` (db/edit/resurvey.h) on the Hamersley DEM: a corrected sheet
// (a window of the DEM with a hill raised in it) goes under two surfaces carrying fill, replace
// and breakline features. Afterwards the store passes the full check against the new cells (the
// tolerance everywhere, paint from the features), each surface is the constrained Delaunay
// triangulation of its vertices and constraints (the exact local test of
// tests/db/update_engine_property_test.cc), triangles away from the sheet keep their rows, the
// features are kept and there is one `changes` row per surface; a rebuild from the new DEM with
// the same features passes the same tests. A sheet may grow the DEM's grid beyond the surfaces;
// one that changes cells by a surface's edge is refused, the store unchanged.
#include "db/edit/resurvey.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "core/geometry/cdt.h"
#include "core/raster/gdal_raster.h"
#include "db/change_log.h"
#include "db/dem_store.h"
#include "db/feature_store.h"
#include "db/integrity_check.h"
#include "db/polygon_editor.h"
#include "db/surface_builder.h"
#include "db/surface_store.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::Ngon;
using testing::TempDir;
using testing::WritePolygons;

// Centre of the Hamersley DEM (EPSG:28350), and its cell size.
constexpr double kCx = 539300, kCy = 7497340, kCell = 344.404386931320971;

// The store has exactly as many triangles as a from-scratch CDT of its vertices and
// constraints; with the full check's invariants 4 and 5 this makes it that CDT.
void ExpectSameAsFromScratch(Store& store, const std::string& name) {
  SurfaceStore surfaces(store);
  auto surface = surfaces.Find(name);
  ASSERT_TRUE(surface.ok());
  auto loaded = surfaces.Load(*surface);
  ASSERT_TRUE(loaded.ok());
  Cdt cdt;
  const std::vector<uint32_t> index = cdt.InsertVertices(loaded->tin.vertices);
  for (const auto& [a, b] : loaded->tin.constraints) cdt.InsertConstraint(index[a], index[b]);
  const Tin scratch = cdt.ToTin([](double, double) { return 0.0; });
  EXPECT_EQ(scratch.vertices.size(), loaded->tin.vertices.size()) << name;
  EXPECT_EQ(scratch.triangles.size(), loaded->tin.triangles.size()) << name;
}

class ResurveyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = testing::StoreTarget(dir_, "s.tinbase");
    auto store = Store::Create(path_, "");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    DemImportOptions dem;
    dem.name = "dtm";
    ASSERT_TRUE(DemStore(*store_).Import({DataPath("geology/hamersley/dtm_rp.tif")}, dem).ok());
    for (auto [name, tolerance] : {std::pair{"terrain", 5.0}, std::pair{"coarse", 20.0}}) {
      SurfaceBuildOptions o;
      o.surface = name;
      o.greedy.tolerance = tolerance;
      auto built = BuildSurfaceFromDem(*store_, o);
      ASSERT_TRUE(built.ok()) << built.status().ToString();
      AddFeatures(name);
    }
  }

  // A fill polygon over the hill's edge, a replace polygon beside it, a breakline across it.
  void AddFeatures(const std::string& surface) {
    PolygonAddOptions o;
    o.surface = surface;
    o.mode = FeatureMode::kFill;
    o.tag = "unit";
    o.file = WritePolygons(dir_, "fill.geojson", {{Ngon(kCx + 4 * kCell, kCy, 6 * kCell, 17)}});
    ASSERT_TRUE(AddPolygons(*store_, o).ok());
    o.mode = FeatureMode::kReplace;
    o.level = 500;
    o.tag.clear();
    o.file = WritePolygons(dir_, "pit.geojson", {{Ngon(kCx - 12 * kCell, kCy, 3 * kCell, 9)}});
    ASSERT_TRUE(AddPolygons(*store_, o).ok());
    o.mode = FeatureMode::kBreakline;
    o.level.reset();
    const std::string line = dir_.Path("line.geojson");
    FILE* f = std::fopen(line.c_str(), "w");
    std::fprintf(f,
                 R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": )"
                 R"({"name": "urn:ogc:def:crs:EPSG::28350"}}, "features": [{"type": "Feature", )"
                 R"("properties": {}, "geometry": {"type": "LineString", "coordinates": )"
                 R"([[%.17g, %.17g], [%.17g, %.17g]]}}]})",
                 kCx - 8 * kCell, kCy - 9 * kCell, kCx + 9 * kCell, kCy + 8 * kCell);
    std::fclose(f);
    o.file = line;
    auto added = AddPolygons(*store_, o);
    ASSERT_TRUE(added.ok()) << added.status().ToString();
  }

  // A sheet of `n` x `n` cells of the DEM from (col0, row0), a hill of `height` metres raised in
  // it (a cone over the middle), written as a GeoTIFF.
  std::string CorrectedSheet(int64_t col0, int64_t row0, int64_t n, double height) {
    auto raster = GdalRaster::Open(DataPath("geology/hamersley/dtm_rp.tif"));
    EXPECT_TRUE(raster.ok());
    auto full = raster->Read();
    EXPECT_TRUE(full.ok());
    Grid sheet = *full;
    sheet.geometry.origin_x = full->geometry.origin_x + static_cast<double>(col0) * kCell;
    sheet.geometry.origin_y =
        full->geometry.origin_y + static_cast<double>(row0) * full->geometry.cell_y;
    sheet.geometry.width = n;
    sheet.geometry.height = n;
    sheet.cells.clear();
    const double mid = static_cast<double>(n - 1) / 2;
    for (int64_t r = 0; r < n; ++r)
      for (int64_t c = 0; c < n; ++c) {
        const double d = std::hypot(static_cast<double>(c) - mid, static_cast<double>(r) - mid);
        const double raise = std::max(0.0, height * (1 - d / mid));
        const bool on_dem = col0 + c < full->geometry.width && row0 + r < full->geometry.height;
        const float z = on_dem ? full->At(col0 + c, row0 + r) : 400.0f;
        sheet.cells.push_back(z + static_cast<float>(raise));
      }
    const std::string path = dir_.Path("sheet" + std::to_string(col0) + ".tif");
    EXPECT_TRUE(WriteGeoTiff(sheet, path).ok());
    return path;
  }

  std::set<int64_t> TriangleIds(const std::string& surface) {
    std::set<int64_t> ids;
    auto stmt = store_->db().Prepare(
        "SELECT t.id FROM triangles t JOIN surfaces s ON s.id = t.surface WHERE s.name = ?");
    EXPECT_TRUE(stmt.ok());
    (*stmt)->Bind(1, surface);
    while (*(*stmt)->Step()) ids.insert((*stmt)->ColumnInt(0));
    return ids;
  }

  TempDir dir_;
  std::string path_;
  std::unique_ptr<Store> store_;
};

TEST_F(ResurveyTest, CorrectedSheetUpdatesEverySurfaceLocally) {
  const std::set<int64_t> before = TriangleIds("terrain");
  auto features_before = LoadFeatures(*store_, *SurfaceStore(*store_).Find("terrain"));
  ASSERT_TRUE(features_before.ok());
  DemImportOptions o;
  o.name = "dtm";
  auto report = ImportUnderSurfaces(*store_, {CorrectedSheet(95, 92, 24, 120)}, o);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  ASSERT_EQ(report->surfaces.size(), 2u);
  for (const SurfaceResurvey& s : report->surfaces) {
    SCOPED_TRACE(s.surface);
    EXPECT_GT(s.cells_missed, 0);
    EXPECT_GT(s.added, 0);
    EXPECT_FALSE(s.whole_surface);
  }
  testing::ExpectStoreIntact(*store_, /*full=*/true);
  ExpectSameAsFromScratch(*store_, "terrain");
  ExpectSameAsFromScratch(*store_, "coarse");
  // Locality: most triangles of the surface keep their rows.
  const std::set<int64_t> after = TriangleIds("terrain");
  size_t kept = 0;
  for (int64_t id : before) kept += after.count(id);
  EXPECT_GT(kept, before.size() * 3 / 4);
  EXPECT_LT(kept, before.size());
  // The features stay, and one changes row per surface.
  auto features_after = LoadFeatures(*store_, *SurfaceStore(*store_).Find("terrain"));
  ASSERT_TRUE(features_after.ok());
  ASSERT_EQ(features_after->size(), features_before->size());
  for (size_t k = 0; k < features_after->size(); ++k)
    EXPECT_EQ((*features_after)[k].id, (*features_before)[k].id);
  auto changes = ChangesSince(*store_, report->surfaces.front().tx - 1);
  ASSERT_TRUE(changes.ok());
  ASSERT_EQ(changes->size(), 2u);
  for (const Change& c : *changes) EXPECT_EQ(c.action, "dem resurvey");
  EXPECT_NE((*changes)[0].surface, (*changes)[1].surface);
}

TEST_F(ResurveyTest, EqualsARebuildFromTheNewDem) {
  DemImportOptions o;
  o.name = "dtm";
  auto report = ImportUnderSurfaces(*store_, {CorrectedSheet(95, 92, 24, 120)}, o);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  // The same features over a surface built from the new cells: both pass the same tests.
  SurfaceBuildOptions b;
  b.surface = "rebuilt";
  b.dem = "dtm";
  b.greedy.tolerance = 5;
  auto built = BuildSurfaceFromDem(*store_, b);
  ASSERT_TRUE(built.ok()) << built.status().ToString();
  AddFeatures("rebuilt");
  testing::ExpectStoreIntact(*store_, /*full=*/true);
  ExpectSameAsFromScratch(*store_, "terrain");
  ExpectSameAsFromScratch(*store_, "rebuilt");
  // The same paint: as many triangles carry the fill's tag, about (the triangulations differ).
  SurfaceStore surfaces(*store_);
  auto resurveyed = surfaces.Count(*surfaces.Find("terrain"));
  auto rebuilt = surfaces.Count(*surfaces.Find("rebuilt"));
  ASSERT_TRUE(resurveyed.ok() && rebuilt.ok());
  EXPECT_EQ(resurveyed->features, rebuilt->features);
  EXPECT_EQ(resurveyed->triangles - resurveyed->visible_triangles,
            rebuilt->triangles - rebuilt->visible_triangles);
}

// A new sheet over nodata: the Hamersley DEM first stored with a hole of nodata near its corner,
// then the whole sheet imported over it. The triangles there come into view (invariant 6 recomputes
// paint) and meet the new cells (invariant 7). The store of the nodata tests: the DEM with a 30 x
// 30 hole of nodata from (first, first), and surface "t" built on it.
std::unique_ptr<Store> StoreWithHole(const TempDir& dir, int64_t first) {
  auto store = Store::Create(testing::StoreTarget(dir, "s.tinbase"), "");
  EXPECT_TRUE(store.ok()) << store.status().ToString();
  auto raster = GdalRaster::Open(DataPath("geology/hamersley/dtm_rp.tif"));
  EXPECT_TRUE(raster.ok());
  auto grid = raster->Read();
  EXPECT_TRUE(grid.ok());
  for (int64_t r = first; r < first + 30; ++r)
    for (int64_t c = first; c < first + 30; ++c)
      grid->cells[static_cast<size_t>(r * grid->geometry.width + c)] = NAN;
  const std::string holed = dir.Path("holed.tif");
  EXPECT_TRUE(WriteGeoTiff(*grid, holed).ok());
  DemImportOptions dem;
  dem.name = "dtm";
  EXPECT_TRUE(DemStore(**store).Import({holed}, dem).ok());
  SurfaceBuildOptions b;
  b.surface = "t";
  b.greedy.tolerance = 5;
  EXPECT_TRUE(BuildSurfaceFromDem(**store, b).ok());
  return std::move(*store);
}

TEST(ResurveyNodataTest, NewSheetOverNodataShowsTheTrianglesThere) {
  TempDir dir;
  std::unique_ptr<Store> store = StoreWithHole(dir, 5);
  auto counts_before = SurfaceStore(*store).Count(*SurfaceStore(*store).Find("t"));
  ASSERT_TRUE(counts_before.ok());
  DemImportOptions dem;
  dem.name = "dtm";
  auto report = ImportUnderSurfaces(*store, {DataPath("geology/hamersley/dtm_rp.tif")}, dem);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  ASSERT_EQ(report->surfaces.size(), 1u);
  EXPECT_GT(report->surfaces[0].cells_missed, 0);
  testing::ExpectStoreIntact(*store, /*full=*/true);
  ExpectSameAsFromScratch(*store, "t");
  auto counts_after = SurfaceStore(*store).Count(*SurfaceStore(*store).Find("t"));
  ASSERT_TRUE(counts_after.ok());
  EXPECT_GT(counts_after->visible_triangles, counts_before->visible_triangles);
}

// The hole at the corner: the new cells on the surface's boundary cannot be met locally.
TEST(ResurveyNodataTest, NewCellsOnTheBoundaryAreRefusedAndChangeNothing) {
  TempDir dir;
  StoreWithHole(dir, 0).reset();
  const auto before = testing::TableChecksums(testing::StoreTarget(dir, "s.tinbase"));
  auto store = Store::Open(testing::StoreTarget(dir, "s.tinbase"));
  ASSERT_TRUE(store.ok());
  DemImportOptions dem;
  dem.name = "dtm";
  auto report = ImportUnderSurfaces(**store, {DataPath("geology/hamersley/dtm_rp.tif")}, dem);
  ASSERT_EQ(report.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(report.status().message().find("surface 't'"), std::string::npos);
  EXPECT_NE(report.status().message().find("lies by the surface's boundary"), std::string::npos)
      << report.status().message();
  store->reset();
  EXPECT_EQ(testing::TableChecksums(testing::StoreTarget(dir, "s.tinbase")), before);
}

// The control: the same sheet imported with the surfaces left as they were breaks the tolerance
// (invariant 7), which the tests above would then see.
TEST_F(ResurveyTest, WithoutTheUpdateTheSurfacesMissTheNewCells) {
  DemImportOptions o;
  o.name = "dtm";
  o.under_surfaces = [](const DemImportReport&) { return Status::Ok(); };
  ASSERT_TRUE(DemStore(*store_).Import({CorrectedSheet(95, 92, 24, 120)}, o).ok());
  auto problems = CheckStore(*store_, {.surface = {}, .full = true});
  ASSERT_TRUE(problems.ok());
  size_t tolerance = 0;
  for (const Problem& p : *problems) tolerance += p.code == "tolerance" ? 1 : 0;
  EXPECT_GT(tolerance, 0u);
}

// A sheet that grows the grid with a hill on the surfaces' edge: refused for the edge, as any
// change there, and the store unchanged.
TEST_F(ResurveyTest, SheetGrowingTheGridWithChangesOnTheEdgeIsRefused) {
  store_.reset();
  const auto before = testing::TableChecksums(path_);
  auto store = Store::Open(path_);
  ASSERT_TRUE(store.ok());
  store_ = std::move(*store);
  DemImportOptions o;
  o.name = "dtm";
  // Columns 180..209 reach past the DEM's 197; the hill's centre is on its last columns.
  auto report = ImportUnderSurfaces(*store_, {CorrectedSheet(180, 50, 30, 50)}, o);
  ASSERT_EQ(report.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(report.status().message().find("lies by the surface's boundary"), std::string::npos)
      << report.status().message();
  store_.reset();
  EXPECT_EQ(testing::TableChecksums(path_), before);
}

// A sheet that grows the grid and leaves the cells under the surfaces as they were: the new cells
// are stored, the surfaces keep their extent (no vertex beyond the old grid's last column of
// centres) and pass the full check against the grown DEM.
TEST_F(ResurveyTest, SheetGrowingTheGridBeyondTheSurfacesIsTaken) {
  auto dem = DemStore(*store_).Find("dtm");
  ASSERT_TRUE(dem.ok());
  const double last_centre = dem->geometry.CellCenterX(dem->geometry.width - 1);
  DemImportOptions o;
  o.name = "dtm";
  auto report = ImportUnderSurfaces(*store_, {CorrectedSheet(190, 50, 20, 0)}, o);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->import.dem.geometry.width, 210);
  EXPECT_EQ(report->surfaces.size(), 2u);
  auto max_x = store_->db().Prepare("SELECT max(x) FROM vertices");
  ASSERT_TRUE(max_x.ok());
  ASSERT_TRUE(*(*max_x)->Step());
  EXPECT_EQ((*max_x)->ColumnDouble(0), last_centre) << "the surfaces do not grow with the grid";
  testing::ExpectStoreIntact(*store_, /*full=*/true);
}

}  // namespace
}  // namespace tinbase
