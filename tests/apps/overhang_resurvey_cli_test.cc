// `dem import --update-surfaces` end to end: a corrected sheet of the Hamersley DEM (a hill raised
// in a window) goes under surface "terrain"; the command says what it did per surface, `check
// --full` passes against the new cells, and `changes --json` (read by nlohmann::json) lists one
// "dem resurvey" row. A sheet that would grow the DEM's grid is refused, the store unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "core/raster/gdal_raster.h"
#include "tests/support/cli_support.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::CliResult;
using testing::DataPath;
using testing::ExpectRejected;
using testing::Quote;
using testing::RunCli;
using testing::RunWrite;
using testing::StoreTarget;
using testing::TempDir;

class ResurveyCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    RunWrite(store_, "init " + Quote(store_));
    RunWrite(store_,
             "dem import " + Quote(store_) + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
    RunWrite(store_, "tin build " + Quote(store_) + " --surface terrain --tolerance 10");
  }

  // `n` x `n` cells of the DEM from (col0, row0) with `raise` metres added (400 m off the DEM).
  std::string Sheet(int64_t col0, int64_t row0, int64_t n, float raise) {
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
      for (int64_t c = col0; c < col0 + n; ++c)
        sheet.cells.push_back((c < g.width && r < g.height ? full->At(c, r) : 400.0f) + raise);
    const std::string path = dir_.Path("sheet" + std::to_string(col0) + ".tif");
    EXPECT_TRUE(WriteGeoTiff(sheet, path).ok());
    return path;
  }

  TempDir dir_;
  std::string store_;
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

TEST_F(ResurveyCliTest, SheetGrowingTheGridIsRefused) {
  ExpectRejected(store_,
                 "dem import " + Quote(store_) + " " + Quote(Sheet(190, 20, 12, 0)) +
                     " --name dtm_rp --update-surfaces",
                 "surfaces 'terrain' are built on it");
}

}  // namespace
}  // namespace tinbase
