// `dem import --update-surfaces` end to end: a corrected sheet of the Hamersley DEM (a hill raised
// in a window) goes under surface "terrain"; the command says what it did per surface, `check
// --full` passes against the new cells, and `changes --json` (read by nlohmann::json) lists one
// "dem resurvey" row. A sheet that grows the DEM's grid is taken where the surface does not
// reach; a change by the surface's edge is refused, the store unchanged. A polygon reaching past
// the surface into the grown cells is clipped to the surface's own extent, not the DEM's.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "core/raster/gdal_raster.h"
#include "tests/support/cli_support.h"
#include "tests/support/store_target.h"
#include "tests/support/store_template.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::CliResult;
using testing::DataPath;
using testing::ExpectRejected;
using testing::Json;
using testing::Quote;
using testing::RunCli;
using testing::RunWrite;
using testing::StoreTarget;
using testing::TempDir;

class ResurveyCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    testing::CopyRecipeStore(testing::HamersleyTerrainRecipe(10), store_);
  }

  // `n` x `n` cells of the DEM from (col0, row0) with `raise` metres added (400 m off the DEM);
  // with `margin`, only to the cells at least that many cells inside the DEM's edge.
  std::string Sheet(int64_t col0, int64_t row0, int64_t n, float raise, int64_t margin = 0) {
    auto raster = GdalRaster::Open(DataPath("geology/hamersley/dtm_rp.tif"));
    EXPECT_TRUE(raster.ok());
    auto full = raster->Read();
    EXPECT_TRUE(full.ok());
    Grid sheet = *full;
    const GridGeometry& g = full->geometry;
    sheet.geometry.origin_x = g.origin_x + static_cast<double>(col0) * g.cell_x;
    sheet.geometry.origin_y = g.origin_y + static_cast<double>(row0) * g.cell_y;
    sheet.geometry.width = sheet.geometry.height = n;
    sheet.cells.clear();
    for (int64_t r = row0; r < row0 + n; ++r)
      for (int64_t c = col0; c < col0 + n; ++c) {
        const bool inside = c < g.width && r < g.height;
        const bool raised =
            c >= margin && c < g.width - margin && r >= margin && r < g.height - margin;
        sheet.cells.push_back((inside ? full->At(c, r) : 400.0f) + (raised ? raise : 0.0f));
      }
    const std::string path = dir_.Path("sheet" + std::to_string(col0) + ".tif");
    EXPECT_TRUE(WriteGeoTiff(sheet, path).ok());
    return path;
  }

  // A rectangle in EPSG:28350, the DEM's CRS, as one GeoJSON polygon feature.
  std::string Rectangle(const std::string& name, double x0, double y0, double x1, double y1) {
    const std::string path = dir_.Path(name);
    std::ofstream out(path);
    out.precision(17);
    out << R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": )"
        << R"("urn:ogc:def:crs:EPSG::28350"}}, "features": [{"type": "Feature", "properties": )"
        << R"({}, "geometry": {"type": "Polygon", "coordinates": [[)"
        << "[" << x0 << "," << y0 << "],[" << x1 << "," << y0 << "],[" << x1 << "," << y1 << "],["
        << x0 << "," << y1 << "],[" << x0 << "," << y0 << "]]]}}]}\n";
    return path;
  }

  // The DEM grown by 8 columns east over rows 20..35 (the cells under the surface as they were);
  // fills the old east edge of the DEM's box (the surface's, half a cell beyond its last
  // vertices), the top of the box and the cell size.
  void GrowTheDem() {
    const nlohmann::json before = Json(RunCli("info --json " + Quote(store_)));
    const int64_t width = before["dems"][0]["width"].get<int64_t>();
    east_ = before["dems"][0]["bbox"][2].get<double>();
    north_ = before["dems"][0]["bbox"][3].get<double>();
    cell_ = before["dems"][0]["cell_size"][0].get<double>();
    RunWrite(store_, "dem import " + Quote(store_) + " " + Quote(Sheet(width - 8, 20, 16, 0)) +
                         " --name dtm_rp --update-surfaces");
  }

  // Rows 24..30 of the DEM, from 10 cells inside the old east edge to 4 cells beyond it (in the
  // grown cells, which have elevation): 4.5 cells by 6 lie outside the surface.
  std::string Overhanging(const std::string& name) {
    return Rectangle(name, east_ - 10 * cell_, north_ - 30 * cell_, east_ + 4 * cell_,
                     north_ - 24 * cell_);
  }

  TempDir dir_;
  std::string store_;
  double east_ = 0;
  double north_ = 0;
  double cell_ = 0;
};

TEST_F(ResurveyCliTest, CorrectedSheetUpdatesTheSurface) {
  const CliResult r =
      RunWrite(store_, "dem import " + Quote(store_) + " " + Quote(Sheet(90, 90, 12, 60)) +
                           " --name dtm_rp --update-surfaces");
  EXPECT_NE(r.out.find("surface 'terrain': "), std::string::npos) << r.out;
  const nlohmann::json changes =
      nlohmann::json::parse(RunCli("changes " + Quote(store_) + " --since 1 --json").out);
  ASSERT_EQ(changes.size(), 1u) << changes.dump();
  EXPECT_EQ(changes[0]["action"], "dem resurvey");
  EXPECT_GT(changes[0]["added"].get<int64_t>(), 0);
}

// A sheet that grows the DEM's grid: the new cells beyond the surface are stored, the surface
// stays where it is and is re-triangulated where the cells under it changed; a change by the
// surface's edge is still refused, the store unchanged.
TEST_F(ResurveyCliTest, SheetGrowingTheGridIsTakenWhereTheSurfaceDoesNotReach) {
  const nlohmann::json before = Json(RunCli("info --json " + Quote(store_)));
  const int64_t width = before["dems"][0]["width"].get<int64_t>();
  const int64_t height = before["dems"][0]["height"].get<int64_t>();
  // Raised by 60 m everywhere, the edge included: refused.
  ExpectRejected(store_,
                 "dem import " + Quote(store_) + " " + Quote(Sheet(width - 8, 20, 16, 60)) +
                     " --name dtm_rp --update-surfaces",
                 "lies by the surface's boundary");
  // Raised 6 or more cells inside the edge only, and grown by 8 columns.
  const CliResult r = RunWrite(store_, "dem import " + Quote(store_) + " " +
                                           Quote(Sheet(width - 8, 20, 16, 60, 6)) +
                                           " --name dtm_rp --update-surfaces");
  EXPECT_NE(r.out.find("surface 'terrain': "), std::string::npos) << r.out;
  const nlohmann::json after = Json(RunCli("info --json " + Quote(store_)));
  EXPECT_EQ(after["dems"][0]["width"].get<int64_t>(), width + 8) << after.dump();
  EXPECT_EQ(after["dems"][0]["height"].get<int64_t>(), height);
  // The surface does not grow with the grid: a new cell's centre lies outside it.
  const auto& bbox = after["dems"][0]["bbox"];
  const double cell = after["dems"][0]["cell_size"][0].get<double>();
  const std::string x = std::to_string(bbox[2].get<double>() - 2.5 * cell);
  const std::string y = std::to_string(0.5 * (bbox[1].get<double>() + bbox[3].get<double>()));
  const CliResult outside =
      RunCli("locate --json " + Quote(store_) + " --surface terrain -- " + x + " " + y);
  EXPECT_NE(outside.exit_code, 0);
  EXPECT_NE(outside.err.find("is outside surface 'terrain'"), std::string::npos) << outside.err;
  const nlohmann::json changes =
      nlohmann::json::parse(RunCli("changes " + Quote(store_) + " --since 1 --json").out);
  ASSERT_EQ(changes.size(), 1u) << changes.dump();
  EXPECT_EQ(changes[0]["action"], "dem resurvey");
  EXPECT_GT(changes[0]["added"].get<int64_t>(), 0) << "the raised cells under it were met";
}

// The data area is the surface's, not the grown DEM's: the overhang into the new cells is cut and
// reported, the store passes the full check; --strict refuses it and changes nothing.
TEST_F(ResurveyCliTest, PolygonIntoGrownCellsIsClippedToTheSurface) {
  GrowTheDem();
  const std::string polygon = Overhanging("over.geojson");
  ExpectRejected(store_,
                 "polygon add " + Quote(store_) + " " + Quote(polygon) +
                     " --surface terrain --mode fill --tag x --strict",
                 "lies outside surface 'terrain'");
  const CliResult r = RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(polygon) +
                                           " --surface terrain --mode fill --tag x --json");
  const nlohmann::json report = nlohmann::json::parse(r.out);
  ASSERT_EQ(report["features"].size(), 1u) << r.out;
  ASSERT_EQ(report["clipped"].size(), 1u) << r.out;
  EXPECT_EQ(report["clipped"][0]["feature"], report["features"][0]);
  EXPECT_EQ(report["clipped"][0]["label"], "over.geojson feature 0");
  EXPECT_NEAR(report["clipped"][0]["area_outside"].get<double>(), 4.5 * 6 * cell_ * cell_,
              1e-3 * cell_ * cell_);
  EXPECT_NE(r.err.find("tinbase: clipped to the surface's data area: over.geojson feature 0"),
            std::string::npos)
      << r.err;
  const CliResult check = RunCli("check --full " + Quote(store_));
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
}

// `polygon update` follows the same rule; `points add` in the grown cells is outside the surface
// (points are never clipped), the store unchanged.
TEST_F(ResurveyCliTest, UpdateIntoGrownCellsIsClippedAndPointsThereRefused) {
  GrowTheDem();
  const std::string inside = Rectangle("inside.geojson", east_ - 10 * cell_, north_ - 30 * cell_,
                                       east_ - 4 * cell_, north_ - 24 * cell_);
  const nlohmann::json added =
      Json(RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(inside) +
                                " --surface terrain --mode fill --tag x --json"));
  ASSERT_EQ(added["features"].size(), 1u) << added.dump();
  const std::string id = std::to_string(added["features"][0].get<int64_t>());
  const CliResult r = RunWrite(store_, "polygon update " + Quote(store_) + " " + id + " " +
                                           Quote(Overhanging("over.geojson")));
  EXPECT_NE(r.err.find("tinbase: clipped to the surface's data area: over.geojson feature 0"),
            std::string::npos)
      << r.err;
  const CliResult check = RunCli("check --full " + Quote(store_));
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  const std::string points = dir_.Path("shots.csv");
  std::ofstream(points) << "x,y,z\n"
                        << std::to_string(east_ + 2 * cell_) << ","
                        << std::to_string(north_ - 27 * cell_) << ",700\n";
  ExpectRejected(store_, "points add " + Quote(store_) + " --surface terrain " + Quote(points),
                 "lies outside surface 'terrain'");
}

}  // namespace
}  // namespace tinbase
