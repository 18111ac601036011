// `tinbase dem info|clip|sample [--nearest] [--points]|import --keep-first` end to end on a real
// SRTM tile.
#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <string>
#include <utility>
#include <vector>

#include "db/dem_store.h"
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

class DemCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    GDALAllRegister();
    store_ = StoreTarget(dir_, "d.tinbase");
    static const testing::StoreRecipe recipe{
        "dem_cli_test", [](const std::string& store, const TempDir&) {
          testing::MakeDemStore(store, "dem/N43E007.hgt", " --block-size 128");
        }};
    testing::CopyRecipeStore(recipe, store_);
  }
  TempDir dir_;
  std::string store_;
};

TEST_F(DemCliTest, InfoListsLevelsAndCompression) {
  auto j = Json(RunCli("dem info --json " + Quote(store_)));
  EXPECT_EQ(j["block_size"], 128);
  ASSERT_GE(j["levels"].size(), 2u);
  for (size_t l = 1; l < j["levels"].size(); ++l) {
    // Each overview halves the level below (rounding up).
    EXPECT_EQ(j["levels"][l]["width"].get<int>(), (j["levels"][l - 1]["width"].get<int>() + 1) / 2);
    EXPECT_DOUBLE_EQ(j["levels"][l]["cell_size"].get<double>(),
                     2 * j["levels"][l - 1]["cell_size"].get<double>());
  }
  // Shuffled zstd of a 16-bit-precision terrain is far smaller than raw float32.
  EXPECT_GT(j["compression_ratio"].get<double>(), 2.0);
  EXPECT_EQ(RunCli("dem info " + Quote(store_)).exit_code, 0);
}

TEST_F(DemCliTest, ClipWritesTheWindowCellForCell) {
  auto info = Json(RunCli("dem info --json " + Quote(store_)));
  const auto& b = info["bbox"];
  const double x0 = b[0].get<double>() + 20000, y0 = b[1].get<double>() + 30000;
  const std::string bbox = std::to_string(x0) + "," + std::to_string(y0) + "," +
                           std::to_string(x0 + 15000) + "," + std::to_string(y0 + 12000);
  const std::string out = dir_.Path("w.tif");
  ASSERT_EQ(RunCli("dem clip " + Quote(store_) + " --bbox " + bbox + " -o " + Quote(out)).exit_code,
            0);
  // The GeoTIFF holds exactly the store's level-0 window.
  auto store = Store::Open(store_, Store::Access::kReadOnly);
  ASSERT_TRUE(store.ok());
  DemStore dems(**store);
  auto dem = dems.Find("N43E007");
  ASSERT_TRUE(dem.ok());
  auto window = dems.ReadWindow(*dem, {x0, y0, x0 + 15000, y0 + 12000}, 0);
  ASSERT_TRUE(window.ok()) << window.status().ToString();
  GDALDatasetUniquePtr ds(GDALDataset::Open(out.c_str(), GDAL_OF_RASTER));
  ASSERT_TRUE(ds);
  ASSERT_EQ(ds->GetRasterXSize(), window->geometry.width);
  ASSERT_EQ(ds->GetRasterYSize(), window->geometry.height);
  std::vector<float> cells(static_cast<size_t>(window->geometry.CellCount()));
  ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, ds->GetRasterXSize(),
                                           ds->GetRasterYSize(), cells.data(), ds->GetRasterXSize(),
                                           ds->GetRasterYSize(), GDT_Float32, 0, 0),
            CE_None);
  for (size_t i = 0; i < cells.size(); ++i) {
    if (!std::isnan(window->cells[i])) {
      ASSERT_EQ(cells[i], window->cells[i]) << i;
    }
  }

  // A large window with a small cell budget comes from an overview.
  const std::string coarse = dir_.Path("c.tif");
  auto r =
      RunCli("dem clip " + Quote(store_) + " --bbox " + std::to_string(b[0].get<double>()) + "," +
             std::to_string(b[1].get<double>()) + "," + std::to_string(b[2].get<double>()) + "," +
             std::to_string(b[3].get<double>()) + " --max-cells 20000 -o " + Quote(coarse));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("from level 0"), std::string::npos) << r.out;
  GDALDatasetUniquePtr small(GDALDataset::Open(coarse.c_str(), GDAL_OF_RASTER));
  ASSERT_TRUE(small);
  EXPECT_LE(int64_t{small->GetRasterXSize()} * small->GetRasterYSize(), 20000);
}

TEST_F(DemCliTest, BadBoxesAreRejectedUnchanged) {
  const std::string s = Quote(store_);
  const std::string o = " -o " + Quote(dir_.Path("x.tif"));
  ExpectRejected(store_, "dem clip " + s + " --bbox 1,2,3" + o, "4 numbers");
  ExpectRejected(store_, "dem clip " + s + " --bbox 5,2,3,4" + o, "min must be below max");
  ExpectRejected(store_, "dem clip " + s + " --bbox a,2,3,4" + o, "'a' is not a number");
  ExpectRejected(store_, "dem clip " + s + " --bbox 0,0,10,10" + o, "does not overlap");
}

TEST_F(DemCliTest, NearestSampleIsACellValue) {
  auto info = Json(RunCli("dem info --json " + Quote(store_)));
  const auto& b = info["bbox"];
  const double x = (b[0].get<double>() + b[2].get<double>()) / 2 + 17.3;
  const double y = (b[1].get<double>() + b[3].get<double>()) / 2 + 11.9;
  const std::string xy = " -- " + std::to_string(x) + " " + std::to_string(y);
  auto nearest = Json(RunCli("dem sample --json --nearest " + Quote(store_) + xy));
  auto bilinear = Json(RunCli("dem sample --json " + Quote(store_) + xy));
  const double z = nearest["z"].get<double>();
  EXPECT_TRUE(std::isfinite(z));
  // The warped .hgt keeps bilinear values between cells; the nearest value is a stored cell,
  // never further than the terrain's local relief from the bilinear one.
  EXPECT_NEAR(z, bilinear["z"].get<double>(), 200.0);
}

// --points samples many points in one call: the same values as one point at a time (the library's
// Sample), "nodata" off the DEM, in input order; bad lines are refused naming file and line.
TEST_F(DemCliTest, ManyPointsInOneCall) {
  auto info = Json(RunCli("dem info --json " + Quote(store_)));
  const auto& b = info["bbox"];
  const double x0 = b[0].get<double>(), y0 = b[1].get<double>();
  const double w = b[2].get<double>() - x0, h = b[3].get<double>() - y0;
  std::vector<std::pair<double, double>> points;
  for (int i = 0; i < 300; ++i)
    points.emplace_back(x0 + w * ((i * 37 % 101) / 100.0), y0 + h * ((i * 53 % 97) / 96.0));
  points.emplace_back(x0 - 1000, y0);  // off the DEM
  const std::string file = dir_.Path("points.csv");
  {
    std::ofstream out(file);
    out << "x,y,label\n# a comment, then a blank line\n\n";
    for (const auto& [x, y] : points) out << std::setprecision(17) << x << "," << y << ",p\n";
  }
  auto store = Store::Open(store_, Store::Access::kReadOnly);
  ASSERT_TRUE(store.ok());
  DemStore dems(**store);
  auto dem = dems.Find("N43E007");
  ASSERT_TRUE(dem.ok()) << dem.status().ToString();
  for (const bool nearest : {false, true}) {
    auto j = Json(RunCli("dem sample --json " + std::string(nearest ? "--nearest " : "") +
                         Quote(store_) + " --points " + Quote(file)));
    ASSERT_EQ(j["points"].size(), points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      const auto& p = j["points"][i];
      EXPECT_EQ(p["x"].get<double>(), points[i].first);
      auto z = dems.Sample(*dem, points[i].first, points[i].second,
                           nearest ? DemSampling::kNearest : DemSampling::kBilinear);
      if (z.ok())
        EXPECT_DOUBLE_EQ(p["z"].get<double>(), *z) << i;
      else
        EXPECT_TRUE(p["z"].is_null()) << i << " " << z.status().ToString();
    }
    EXPECT_TRUE(j["points"].back()["z"].is_null());
  }
  CliResult text = RunCli("dem sample " + Quote(store_) + " --points " + Quote(file));
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_EQ(std::count(text.out.begin(), text.out.end(), '\n'),
            static_cast<std::ptrdiff_t>(points.size()));
  EXPECT_NE(text.out.find(" nodata\n"), std::string::npos);

  const std::string bad = dir_.Path("bad.txt");
  std::ofstream(bad) << "1 2\n3 4\n5 north\n";
  ExpectRejected(store_, "dem sample " + Quote(store_) + " --points " + Quote(bad),
                 "bad.txt:3: 'north' is not a number");
  std::ofstream(bad) << "1 2\n7\n";
  ExpectRejected(store_, "dem sample " + Quote(store_) + " --points " + Quote(bad),
                 "bad.txt:2: expected 'x y' or 'x,y'");
  ExpectRejected(store_, "dem sample " + Quote(store_) + " --points " + Quote(dir_.Path("none")),
                 "cannot open the points file");
  ExpectRejected(store_, "dem sample " + Quote(store_), "either a point (X Y) or --points");
}

}  // namespace
}  // namespace tinbase
