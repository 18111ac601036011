// A DEM larger than the memory its commands may use: 20000 x 20000 float32 cells (1.6 GB) imported
// sheet by sheet, then a greedy surface built and fully checked with the block cache held to
// 64 MiB, each command's peak memory measured. Issue 4: greedy "works on DEMs larger than memory
// by streaming blocks".
#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/cli_support.h"
#include "tests/support/store_target.h"

namespace tinbase {
namespace {

using testing::CliResult;
using testing::Quote;
using testing::RunCli;
using testing::StoreTarget;
using testing::TempDir;

constexpr int kSide = 20000;   // cells
constexpr int kSheet = 5000;   // cells per sheet side: 16 sheets of 100 MB
constexpr double kCell = 5.0;  // metres
constexpr double kOriginX = 500000, kOriginY = 5300000;

// Smooth hills and valleys with detail down to a few hundred metres, so a 2 m tolerance needs
// tens of thousands of points spread over the whole DEM (and so every block).
double Terrain(double x, double y) {
  return 400 + 300 * std::sin(x / 7000) * std::cos(y / 5000) + 60 * std::sin((x + y) / 1300) +
         8 * std::sin(x / 170) * std::sin(y / 230);
}

// Writes the sheet whose north-west cell is (col0, row0) of the big grid as a GeoTIFF.
void WriteSheet(const std::string& path, int col0, int row0) {
  GDALAllRegister();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  GDALDataset* ds = driver->Create(path.c_str(), kSheet, kSheet, 1, GDT_Float32, nullptr);
  ASSERT_NE(ds, nullptr);
  double gt[6] = {kOriginX + col0 * kCell, kCell, 0, kOriginY - row0 * kCell, 0, -kCell};
  ds->SetGeoTransform(gt);
  OGRSpatialReference srs;
  srs.importFromEPSG(32632);
  ds->SetSpatialRef(&srs);
  std::vector<float> row(kSheet);
  for (int r = 0; r < kSheet; ++r) {
    const double y = gt[3] - (r + 0.5) * kCell - kOriginY;
    for (int c = 0; c < kSheet; ++c)
      row[c] = static_cast<float>(Terrain(gt[0] + (c + 0.5) * kCell - kOriginX, y));
    ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, r, kSheet, 1, row.data(), kSheet, 1,
                                             GDT_Float32, 0, 0),
              CE_None);
  }
  GDALClose(ds);
}

TEST(LargeDemTest, GreedyStreamsADemLargerThanItsMemory) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "big.tinbase");
  ASSERT_EQ(RunCli("init " + Quote(store)).exit_code, 0);
  for (int row0 = 0; row0 < kSide; row0 += kSheet) {
    for (int col0 = 0; col0 < kSide; col0 += kSheet) {
      const std::string sheet = dir.Path("sheet.tif");
      WriteSheet(sheet, col0, row0);
      const CliResult r = RunCli("dem import " + Quote(store) + " " + Quote(sheet) + " --name big");
      ASSERT_EQ(r.exit_code, 0) << r.err;
      std::filesystem::remove(sheet);
    }
  }
  const auto info = testing::Json(RunCli("dem info --json " + Quote(store) + " --name big"));
  ASSERT_EQ(info["width"].get<int64_t>(), kSide) << info.dump();
  ASSERT_EQ(info["height"].get<int64_t>(), kSide);

  // The DEM holds 1.6 GB of cells. With 64 MiB of block cache, a command that streams it keeps
  // a small part of that resident; one that read it whole could not stay under the bound.
  constexpr int64_t kDemKib = int64_t{kSide} * kSide * 4 / 1024;
  // No memory map either: its pages are file cache, but they count as resident.
  const std::string limited = "TINBASE_DEM_CACHE_MIB=64 TINBASE_MMAP_MIB=0";
  const CliResult build =
      RunCli("tin build " + Quote(store) + " --surface s --tolerance 2", limited);
  ASSERT_EQ(build.exit_code, 0) << build.err;
  EXPECT_LT(build.peak_rss_kib, kDemKib / 3) << build.out;
  const auto surface = testing::Json(RunCli("info --json " + Quote(store)))["surfaces"][0];
  EXPECT_GT(surface["vertices"].get<int64_t>(), 10000) << surface.dump();

  // Invariant 7 against every one of the 4e8 cells, streamed the same way.
  const CliResult check = RunCli("check --full " + Quote(store), limited);
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  EXPECT_LT(check.peak_rss_kib, kDemKib / 3);
}

}  // namespace
}  // namespace tinbase
