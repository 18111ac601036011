// Reading a stored DEM: sampling through the block cache agrees with GDAL, overview levels are the
// means of the cells below, windows and clips match the source as gdal_translate cuts it.

#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <set>
#include <thread>

#include "core/raster/gdal_raster.h"
#include "db/dem_store.h"
#include "db/migrations.h"
#include "db/sql/connection.h"
#include "db/store.h"
#include "tests/support/dem_checks.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::CountDifferences;
using testing::DataPath;
using testing::ExpectedBlocks;
using testing::HalveForTest;
using testing::MakeStore;
using testing::OpenRaster;
using testing::Options;
using testing::TableChecksums;
using testing::TempDir;
using testing::WholeBox;

// ---- Sampling through the process-wide block cache.

// Nearest equals GDAL's cell under the point, bilinear in SampleMany equals Sample to the bit, and
// points outside or on nodata come back NaN, on the real Vinschgau DEM (Float32 with nodata).
TEST(DemSampling, ManyPointsNearestAndBilinearAgreeWithGdalAndSample) {
  TempDir dir;
  auto store = MakeStore(dir, "");
  DemStore dems(*store);
  const std::string file = DataPath("dem/elev_vinschgau.tif");
  ASSERT_TRUE(dems.Import({file}, Options("v", 64)).ok());
  auto dem = dems.Find("v");
  ASSERT_TRUE(dem.ok());
  GdalRaster raster = OpenRaster(file);
  const Grid source = *raster.Read();
  const GridGeometry& g = source.geometry;
  std::mt19937 rng(7);
  // 10% of the points fall outside the DEM.
  std::uniform_real_distribution<double> ux(g.MinX() - 0.05 * (g.MaxX() - g.MinX()),
                                            g.MaxX() + 0.05 * (g.MaxX() - g.MinX()));
  std::uniform_real_distribution<double> uy(g.MinY() - 0.05 * (g.MaxY() - g.MinY()),
                                            g.MaxY() + 0.05 * (g.MaxY() - g.MinY()));
  std::vector<double> xs(5000), ys(5000), nearest(5000), bilinear(5000);
  for (size_t i = 0; i < xs.size(); ++i) {
    xs[i] = ux(rng);
    ys[i] = uy(rng);
  }
  ASSERT_TRUE(dems.SampleMany(*dem, xs, ys, nearest, DemSampling::kNearest).ok());
  ASSERT_TRUE(dems.SampleMany(*dem, xs, ys, bilinear).ok());
  GDALRasterBand* band = raster.dataset()->GetRasterBand(1);
  int has_nodata = 0;
  const double nodata = band->GetNoDataValue(&has_nodata);
  ASSERT_TRUE(has_nodata);
  int outside = 0, no_data = 0, valid = 0;
  for (size_t i = 0; i < xs.size(); ++i) {
    SCOPED_TRACE("point " + std::to_string(xs[i]) + ", " + std::to_string(ys[i]));
    if (!g.Contains(xs[i], ys[i])) {
      ++outside;
      EXPECT_TRUE(std::isnan(nearest[i]));
      EXPECT_TRUE(std::isnan(bilinear[i]));
      EXPECT_EQ(dems.Sample(*dem, xs[i], ys[i]).status().code(), StatusCode::kInvalidArgument);
      continue;
    }
    const int col = std::min(static_cast<int>(std::floor((xs[i] - g.origin_x) / g.cell_x)),
                             static_cast<int>(g.width) - 1);
    const int row = std::min(static_cast<int>(std::floor((ys[i] - g.origin_y) / g.cell_y)),
                             static_cast<int>(g.height) - 1);
    double cell = 0;
    ASSERT_EQ(band->RasterIO(GF_Read, col, row, 1, 1, &cell, 1, 1, GDT_Float64, 0, 0, nullptr),
              CE_None);
    if (cell == nodata) {
      ++no_data;
      EXPECT_TRUE(std::isnan(nearest[i]));
      EXPECT_EQ(dems.Sample(*dem, xs[i], ys[i], DemSampling::kNearest).status().code(),
                StatusCode::kNotFound);
    } else {
      ++valid;
      EXPECT_EQ(nearest[i], cell);
    }
    auto one = dems.Sample(*dem, xs[i], ys[i]);
    if (one.ok()) {
      EXPECT_EQ(*one, bilinear[i]);
    } else {
      EXPECT_EQ(one.status().code(), StatusCode::kNotFound);
      EXPECT_TRUE(std::isnan(bilinear[i]));
    }
  }
  EXPECT_GT(outside, 100);
  EXPECT_GT(no_data, 10);
  EXPECT_GT(valid, 1000);
  std::vector<double> short_out(3);
  EXPECT_EQ(dems.SampleMany(*dem, xs, ys, short_out).code(), StatusCode::kInvalidArgument);
}

TEST(DemOverviews, EachLevelIsTheMeanOfTheValidCellsBelow) {
  TempDir dir;
  auto store = MakeStore(dir, "");
  DemStore dems(*store);
  auto report = dems.Import({DataPath("dem/elev_vinschgau.tif")}, Options("v", 32));
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  const DemInfo& dem = report->dem;
  Grid expected = *OpenRaster(DataPath("dem/elev_vinschgau.tif")).Read();
  int levels = 1;  // until one 32 x 32 block holds the level
  for (int64_t w = 252, h = 194; w > 32 || h > 32; w = (w + 1) / 2, h = (h + 1) / 2) ++levels;
  EXPECT_EQ(levels, 4);
  EXPECT_EQ(dem.levels, levels);
  EXPECT_EQ(dems.Find("v")->levels, levels);
  EXPECT_GT(report->overview_blocks_written, 0);
  for (int level = 1; level < dem.levels; ++level) {
    SCOPED_TRACE("level " + std::to_string(level));
    expected = HalveForTest(expected);
    auto window = dems.ReadWindow(dem, WholeBox(dem.geometry), level);
    ASSERT_TRUE(window.ok()) << window.status().ToString();
    EXPECT_EQ(CountDifferences(*window, expected), 0);
  }
  auto stored = store->db().QueryInt("SELECT count(*) FROM dem_blocks WHERE level = 3");
  EXPECT_EQ(*stored, 1);
  auto beyond = dems.ReadWindow(dem, WholeBox(dem.geometry), dem.levels);
  EXPECT_EQ(beyond.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(beyond.status().message().find("DEM 'v' has no level 4 (levels 0 to 3)"),
            std::string::npos)
      << beyond.status().message();
}

TEST(DemWindow, WindowsAndBlocksMatchTheSource) {
  TempDir dir;
  auto store = MakeStore(dir, "");
  DemStore dems(*store);
  auto report = dems.Import({DataPath("dem/elev_vinschgau.tif")}, Options("v", 32));
  ASSERT_TRUE(report.ok());
  const DemInfo& dem = report->dem;
  const Grid source = *OpenRaster(DataPath("dem/elev_vinschgau.tif")).Read();
  const GridGeometry& g = source.geometry;

  // Columns 40..99 and rows 30..69, the box edges a quarter cell inside those cells.
  const DemBox box{g.origin_x + 40.25 * g.cell_x, g.origin_y + 69.75 * g.cell_y,
                   g.origin_x + 99.75 * g.cell_x, g.origin_y + 30.25 * g.cell_y};
  auto window = dems.ReadWindow(dem, box);
  ASSERT_TRUE(window.ok()) << window.status().ToString();
  ASSERT_EQ(window->geometry.width, 60);
  ASSERT_EQ(window->geometry.height, 40);
  EXPECT_DOUBLE_EQ(window->geometry.origin_x, g.origin_x + 40 * g.cell_x);
  EXPECT_DOUBLE_EQ(window->geometry.origin_y, g.origin_y + 30 * g.cell_y);
  for (int64_t r = 0; r < 40; ++r)
    for (int64_t c = 0; c < 60; ++c) {
      const float a = window->At(c, r);
      const float b = source.At(c + 40, r + 30);
      ASSERT_TRUE(a == b || (std::isnan(a) && std::isnan(b))) << c << ", " << r;
    }

  // A box hanging over the north-west corner is clipped to the DEM.
  auto corner = dems.ReadWindow(dem, DemBox{g.MinX() - 1000, g.MaxY() - 5 * 250 + 1,
                                            g.MinX() + 3 * 250 - 1, g.MaxY() + 1000});
  ASSERT_TRUE(corner.ok());
  EXPECT_EQ(corner->geometry.width, 3);
  EXPECT_EQ(corner->geometry.height, 5);
  EXPECT_DOUBLE_EQ(corner->geometry.origin_x, g.origin_x);

  auto away = dems.ReadWindow(dem, DemBox{0, 0, 10, 10});
  EXPECT_EQ(away.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(away.status().message().find("does not overlap DEM 'v'"), std::string::npos);
  auto inverted = dems.ReadWindow(dem, DemBox{box.max_x, box.min_y, box.min_x, box.max_y});
  EXPECT_EQ(inverted.status().code(), StatusCode::kInvalidArgument);

  // Blocks: columns 40..99 are blocks 1..3, rows 30..69 blocks 0..2, where they hold data.
  std::set<std::pair<int64_t, int64_t>> expected;
  for (const auto& [key, range] : ExpectedBlocks(source, 32))
    if (key.first >= 1 && key.first <= 3 && key.second <= 2) expected.insert(key);
  std::set<std::pair<int64_t, int64_t>> visited;
  std::pair<int64_t, int64_t> previous{-1, -1};
  Status status = dems.ForEachBlock(dem, box, 0, [&](const DemBlock& block) {
    EXPECT_LT(std::make_pair(previous.second, previous.first), std::make_pair(block.by, block.bx));
    previous = {block.bx, block.by};
    visited.emplace(block.bx, block.by);
    EXPECT_EQ(block.geometry.width, 32);
    EXPECT_DOUBLE_EQ(block.geometry.origin_x, g.origin_x + 32.0 * block.bx * g.cell_x);
    for (int64_t r = 0; r < 32; ++r)
      for (int64_t c = 0; c < 32; ++c) {
        const int64_t sc = block.bx * 32 + c;
        const int64_t sr = block.by * 32 + r;
        const float v = (*block.cells)[static_cast<size_t>(r * 32 + c)];
        if (sc >= g.width || sr >= g.height) {
          EXPECT_TRUE(std::isnan(v));
          continue;
        }
        const float want = source.At(sc, sr);
        EXPECT_TRUE(v == want || (std::isnan(v) && std::isnan(want)));
        if (!std::isnan(v)) {
          EXPECT_LE(block.zmin, v);
          EXPECT_GE(block.zmax, v);
        }
      }
    return Status::Ok();
  });
  EXPECT_TRUE(status.ok()) << status.ToString();
  EXPECT_EQ(visited, expected);

  int calls = 0;
  Status stop = dems.ForEachBlock(dem, box, 0, [&](const DemBlock&) {
    ++calls;
    return Status::Conflict("enough");
  });
  EXPECT_EQ(stop.code(), StatusCode::kConflict);
  EXPECT_EQ(calls, 1);
}

// gdal_translate of `source` with `args` into an in-memory GeoTIFF, read back as a Grid.
Grid TranslateForTest(const std::string& source, const std::vector<std::string>& args) {
  static int serial = 0;
  const std::string path = "/vsimem/clip_reference_" + std::to_string(++serial) + ".tif";
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  GDALDatasetH in = GDALOpen(source.c_str(), GA_ReadOnly);
  EXPECT_NE(in, nullptr);
  GDALTranslateOptions* options = GDALTranslateOptionsNew(argv.data(), nullptr);
  GDALDatasetH out = GDALTranslate(path.c_str(), in, options, nullptr);
  GDALTranslateOptionsFree(options);
  EXPECT_NE(out, nullptr);
  GDALClose(out);
  GDALClose(in);
  Grid grid = *OpenRaster(path).Read();
  VSIUnlink(path.c_str());
  return grid;
}

std::string Num17(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

TEST(DemClip, WritesTheWindowLikeGdalTranslate) {
  TempDir dir;
  auto store = MakeStore(dir, "");
  DemStore dems(*store);
  auto report = dems.Import({DataPath("dem/elev_vinschgau.tif")}, Options("v", 32));
  ASSERT_TRUE(report.ok());
  const DemInfo& dem = report->dem;
  const GridGeometry& g = dem.geometry;
  // Columns 20..119, rows 10..89: on even cells, so level 1 windows line up too.
  const DemBox box{g.origin_x + 20 * g.cell_x, g.origin_y + 90 * g.cell_y,
                   g.origin_x + 120 * g.cell_x, g.origin_y + 10 * g.cell_y};
  const std::vector<std::string> projwin = {"-projwin", Num17(box.min_x), Num17(box.max_y),
                                            Num17(box.max_x), Num17(box.min_y)};

  const std::string full = dir.Path("full.tif");
  auto clip = dems.Clip(dem, box, 100 * 80, full);
  ASSERT_TRUE(clip.ok()) << clip.status().ToString();
  EXPECT_EQ(clip->level, 0);
  std::vector<std::string> args = {"-of", "GTiff", "-ot", "Float32"};
  args.insert(args.end(), projwin.begin(), projwin.end());
  const Grid reference = TranslateForTest(DataPath("dem/elev_vinschgau.tif"), args);
  const GdalRaster written = OpenRaster(full);
  EXPECT_TRUE(written.crs().IsSame(OpenRaster(DataPath("dem/elev_vinschgau.tif")).crs()));
  EXPECT_EQ(written.nodata().has_value(), true);
  EXPECT_EQ(CountDifferences(*written.Read(), reference), 0);

  // Fewer cells allowed: the finest overview that fits, against gdal_translate's averaging.
  const std::string half = dir.Path("half.tif");
  clip = dems.Clip(dem, box, 100 * 80 / 4, half);
  ASSERT_TRUE(clip.ok()) << clip.status().ToString();
  EXPECT_EQ(clip->level, 1);
  args = {"-of",
          "GTiff",
          "-ot",
          "Float32",
          "-r",
          "average",
          "-tr",
          Num17(2 * g.cell_x),
          Num17(-2 * g.cell_y)};
  args.insert(args.end(), projwin.begin(), projwin.end());
  const Grid averaged = TranslateForTest(DataPath("dem/elev_vinschgau.tif"), args);
  const Grid level1 = *OpenRaster(half).Read();
  ASSERT_EQ(level1.geometry.width, 50);
  ASSERT_EQ(averaged.cells.size(), level1.cells.size());
  EXPECT_DOUBLE_EQ(level1.geometry.origin_x, averaged.geometry.origin_x);
  EXPECT_DOUBLE_EQ(level1.geometry.cell_x, averaged.geometry.cell_x);
  int64_t compared = 0;
  for (size_t i = 0; i < averaged.cells.size(); ++i) {
    ASSERT_EQ(std::isnan(level1.cells[i]), std::isnan(averaged.cells[i])) << i;
    if (std::isnan(averaged.cells[i])) continue;
    EXPECT_NEAR(level1.cells[i], averaged.cells[i], 1e-3) << i;
    ++compared;
  }
  EXPECT_GT(compared, 1500);  // of the 50 x 40 cells, most hold data

  auto bad = dems.Clip(dem, box, 1000, dir.Path("no/such/dir/x.tif"));
  EXPECT_EQ(bad.status().code(), StatusCode::kIOError);
  EXPECT_NE(bad.status().message().find(dir.Path("no/such/dir/x.tif")), std::string::npos);
}

}  // namespace
}  // namespace tinbase
