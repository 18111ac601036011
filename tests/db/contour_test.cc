// dem from-contours in the store: GDAL's contours of a real DEM rebuilt into a blocked DEM that
// matches the original, and every bad input refused with a message naming the thing and the
// place, leaving the store exactly as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "db/contour_import.h"
#include "db/dem_store.h"
#include "tests/support/make_contours.h"
#include "tests/support/read_grid.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::TableChecksums;
using testing::TempDir;

// A GeoJSON file of LineStrings in EPSG:32632 with the given property JSON per line.
std::string WriteLines(const TempDir& dir, const std::string& name,
                       const std::vector<std::pair<std::string, std::string>>& lines) {
  const std::string path = dir.Path(name);
  std::ofstream out(path);
  out << R"({"type":"FeatureCollection","crs":{"type":"name","properties":{"name":)"
      << R"("urn:ogc:def:crs:EPSG::32632"}},"features":[)";
  for (size_t i = 0; i < lines.size(); ++i) {
    out << (i ? "," : "") << R"({"type":"Feature","properties":)" << lines[i].second
        << R"(,"geometry":{"type":"LineString","coordinates":)" << lines[i].first << "}}";
  }
  out << "]}";
  return path;
}

class ContourImportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_path_ = testing::StoreTarget(dir_, "s.tinbase");
    auto store = Store::Create(store_path_, "");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(store).value();
    contours_ = dir_.Path("contours.gpkg");
    ASSERT_TRUE(testing::MakeContours(DataPath("dem/elev_vinschgau.tif"), contours_, 50).ok());
  }

  Result<ContourImportReport> Import(const std::string& path, const std::string& field,
                                     const std::string& name, double cell = 250) {
    ContourImportOptions options;
    options.path = path;
    options.field = field;
    options.cell = cell;
    options.name = name;
    return ImportContourDem(*store_, options);
  }

  // The import must fail with `code` and a message containing `expected`, changing nothing.
  void ExpectRefused(const std::string& path, const std::string& field, const std::string& name,
                     StatusCode code, const std::string& expected, double cell = 250) {
    const auto before = TableChecksums(store_path_);
    auto report = Import(path, field, name, cell);
    ASSERT_FALSE(report.ok()) << "accepted: " << path;
    EXPECT_EQ(report.status().code(), code) << report.status().ToString();
    EXPECT_NE(report.status().message().find(expected), std::string::npos)
        << report.status().message();
    EXPECT_EQ(TableChecksums(store_path_), before);
    testing::ExpectStoreIntact(*store_);
  }

  TempDir dir_;
  std::string store_path_;
  std::unique_ptr<Store> store_;
  std::string contours_;
};

TEST_F(ContourImportTest, RebuildsTheVinschgauDemFromItsContours) {
  auto report = Import(contours_, "ELEV", "from_contours");
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  testing::ExpectStoreIntact(*store_);
  EXPECT_EQ(report->contours.flat_triangles_left, 0);
  EXPECT_GT(report->contours.steiner_points, 0);
  EXPECT_FALSE(report->dem.warped);
  auto crs = store_->GetCrs();
  ASSERT_TRUE(crs.ok() && crs->has_value());
  EXPECT_EQ((*crs)->Epsg(), 32632);

  DemStore dems(*store_);
  auto dem = dems.Find("from_contours");
  ASSERT_TRUE(dem.ok()) << dem.status().ToString();
  EXPECT_EQ(dem->geometry.cell_x, 250);
  auto rebuilt = dems.ReadGrid(*dem);
  ASSERT_TRUE(rebuilt.ok());
  auto original = testing::ReadGridWithGdal(DataPath("dem/elev_vinschgau.tif"));
  ASSERT_TRUE(original.ok());
  double sum_sq = 0;
  int64_t compared = 0;
  for (int64_t r = 0; r < rebuilt->geometry.height; ++r) {
    for (int64_t c = 0; c < rebuilt->geometry.width; ++c) {
      if (!rebuilt->IsValid(c, r)) continue;
      const double want = original->SampleBilinear(rebuilt->geometry.CellCenterX(c),
                                                   rebuilt->geometry.CellCenterY(r));
      if (std::isnan(want)) continue;
      sum_sq += (rebuilt->At(c, r) - want) * (rebuilt->At(c, r) - want);
      ++compared;
    }
  }
  EXPECT_GT(compared, 35000);
  // A quarter of the 50 m contour interval.
  EXPECT_LT(std::sqrt(sum_sq / static_cast<double>(compared)), 12.5);

  // The name is now taken.
  ExpectRefused(contours_, "ELEV", "from_contours", StatusCode::kConflict, "already exists");
}

TEST_F(ContourImportTest, CrossingContoursNameBothFeaturesAndThePoint) {
  const std::string path =
      WriteLines(dir_, "crossing.geojson",
                 {{"[[600000,5170000],[601000,5171000]]", R"({"ELEV":1500})"},
                  {"[[600000,5171000],[600400,5170600],[601000,5170000]]", R"({"ELEV":1550})"},
                  {"[[602000,5170000],[603000,5170000]]", R"({"ELEV":1600})"}});
  ExpectRefused(path, "ELEV", "x", StatusCode::kInvalidArgument,
                "crossing.geojson feature 0 (level 1500) and crossing.geojson feature 1 (level "
                "1550) cross at (600500, 5170500)");
}

TEST_F(ContourImportTest, MissingEmptyOrNonNumericFieldIsRefused) {
  const std::string lines = R"([[600000,5170000],[601000,5171000],[601000,5172000]])";
  ExpectRefused(WriteLines(dir_, "a.geojson", {{lines, R"({"HEIGHT":10})"}}), "ELEV", "x",
                StatusCode::kInvalidArgument, "a.geojson: no field 'ELEV' (fields: HEIGHT)");
  ExpectRefused(WriteLines(dir_, "b.geojson", {{lines, R"({"ELEV":"high"})"}}), "ELEV", "x",
                StatusCode::kInvalidArgument,
                "b.geojson feature 0: field 'ELEV' is not a number (\"high\")");
  ExpectRefused(
      WriteLines(dir_, "c.geojson", {{lines, R"({"ELEV":5})"}, {lines, R"({"ELEV":null})"}}),
      "ELEV", "x", StatusCode::kInvalidArgument, "c.geojson feature 1: field 'ELEV' is empty");
  // A number written as text is a number.
  auto report = Import(
      WriteLines(dir_, "d.geojson",
                 {{lines, R"({"ELEV":"100"})"},
                  {"[[600500,5170000],[601500,5171000],[601500,5172000]]", R"({"ELEV":"110"})"}}),
      "ELEV", "text_levels", 50);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  testing::ExpectStoreIntact(*store_);
}

TEST_F(ContourImportTest, BadOptionsAndFilesAreRefused) {
  ExpectRefused(contours_, "ELEV", "x", StatusCode::kInvalidArgument, "cell size", 0);
  ExpectRefused(contours_, "ELEV", "", StatusCode::kInvalidArgument, "needs a name");
  ExpectRefused(dir_.Path("none.gpkg"), "ELEV", "x", StatusCode::kNotFound, "none.gpkg");
  ExpectRefused(contours_, "NOPE", "x", StatusCode::kInvalidArgument, "no field 'NOPE'");
}

}  // namespace
}  // namespace tinbase
