// GdalRaster: opens GeoTIFF, SRTM .hgt, ASCII grid and zipped rasters; reads band 1 with nodata as
// NaN; warps with square cells, optionally onto a given grid.
#include "core/raster/gdal_raster.h"

#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>

#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::TempDir;

// Runs gdal_translate's library form with `args` from `src` to `dst`.
void Translate(const std::string& src, const std::string& dst, std::vector<const char*> args) {
  EnsureGdalRegistered();
  args.push_back(nullptr);
  GDALDatasetH in = GDALOpen(src.c_str(), GA_ReadOnly);
  ASSERT_NE(in, nullptr);
  GDALTranslateOptions* options = GDALTranslateOptionsNew(const_cast<char**>(args.data()), nullptr);
  GDALDatasetH out = GDALTranslate(dst.c_str(), in, options, nullptr);
  GDALTranslateOptionsFree(options);
  ASSERT_NE(out, nullptr);
  GDALClose(out);
  GDALClose(in);
}

void ExpectSameCells(const Grid& a, const Grid& b) {
  ASSERT_EQ(a.cells.size(), b.cells.size());
  int64_t differences = 0;
  for (size_t i = 0; i < a.cells.size(); ++i)
    if (!(a.cells[i] == b.cells[i] || (std::isnan(a.cells[i]) && std::isnan(b.cells[i]))))
      ++differences;
  EXPECT_EQ(differences, 0);
}

TEST(GdalRaster, ReadsHgtWithVoidsAsNaN) {
  auto raster = GdalRaster::Open(DataPath("dem/N43E007.hgt"));
  ASSERT_TRUE(raster.ok()) << raster.status().ToString();
  EXPECT_EQ(raster->geometry().width, 1201);
  EXPECT_EQ(raster->nodata().value_or(0), -32768);
  EXPECT_TRUE(raster->crs().IsGeographic());
  auto grid = raster->Read();
  ASSERT_TRUE(grid.ok());
  int64_t voids = 0;
  float lowest = 1e9f;
  for (float v : grid->cells) {
    if (std::isnan(v)) {
      ++voids;
    } else {
      lowest = std::min(lowest, v);
    }
  }
  EXPECT_EQ(voids, 1595);  // the data README's count of -32768 cells
  EXPECT_EQ(lowest, -11);
}

TEST(GdalRaster, OpensZippedAndAsciiGridCopiesWithTheSameCells) {
  TempDir dir;
  auto original = GdalRaster::Open(DataPath("dem/elev.tif"));
  ASSERT_TRUE(original.ok());
  auto cells = original->Read();
  ASSERT_TRUE(cells.ok());

  // A zip member is written sequentially (GTiff needs random access), so copy the file's bytes.
  const std::string zipped = "/vsizip/" + dir.Path("elev.zip") + "/inner/elev.tif";
  {
    std::ifstream in(DataPath("dem/elev.tif"), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    VSILFILE* out = VSIFOpenL(zipped.c_str(), "wb");
    ASSERT_NE(out, nullptr);
    ASSERT_EQ(VSIFWriteL(bytes.data(), 1, bytes.size(), out), bytes.size());
    ASSERT_EQ(VSIFCloseL(out), 0);
  }
  auto from_zip = GdalRaster::Open(zipped);
  ASSERT_TRUE(from_zip.ok()) << from_zip.status().ToString();
  ExpectSameCells(*from_zip->Read(), *cells);

  const std::string ascii = dir.Path("elev.asc");
  Translate(DataPath("dem/elev.tif"), ascii, {"-of", "AAIGrid"});
  auto from_ascii = GdalRaster::Open(ascii);
  ASSERT_TRUE(from_ascii.ok()) << from_ascii.status().ToString();
  EXPECT_TRUE(from_ascii->crs().IsSame(original->crs()));
  ExpectSameCells(*from_ascii->Read(), *cells);
}

TEST(GdalRaster, ErrorsNameTheFile) {
  TempDir dir;
  auto missing = GdalRaster::Open(dir.Path("gone.tif"));
  EXPECT_EQ(missing.status().code(), StatusCode::kNotFound);
  EXPECT_EQ(missing.status().message(), dir.Path("gone.tif") + ": no such file");
  auto directory = GdalRaster::Open(dir.dir());
  EXPECT_EQ(directory.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(directory.status().message().find(dir.dir() + ": "), std::string::npos);
  // An ASCII grid without .prj has a geotransform but no CRS.
  const std::string asc = dir.Path("bare.asc");
  std::ofstream(asc) << "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3 4\n";
  auto bare = GdalRaster::Open(asc);
  EXPECT_EQ(bare.status().message(), asc + ": raster has no CRS");
}

TEST(GdalRaster, WarpKeepsSquareCellsAndCanSnapToAGrid) {
  auto raster = GdalRaster::Open(DataPath("dem/elev.tif"));
  ASSERT_TRUE(raster.ok());
  auto utm = Crs::FromUserInput("EPSG:32631");
  ASSERT_TRUE(utm.ok());
  auto free = raster->WarpTo(*utm);
  ASSERT_TRUE(free.ok()) << free.status().ToString();
  EXPECT_TRUE(free->warped());
  EXPECT_EQ(free->geometry().cell_x, -free->geometry().cell_y);
  EXPECT_TRUE(free->crs().IsSame(*utm));

  // Snapped onto a 100 m grid whose lines pass through (12.5, 7.5).
  GridGeometry align{12.5, 7.5, 100, -100, 1, 1};
  auto snapped = raster->WarpTo(*utm, &align);
  ASSERT_TRUE(snapped.ok()) << snapped.status().ToString();
  const GridGeometry& g = snapped->geometry();
  EXPECT_EQ(g.cell_x, 100);
  EXPECT_EQ(g.cell_y, -100);
  EXPECT_NEAR(std::remainder(g.origin_x - 12.5, 100), 0, 1e-6);
  EXPECT_NEAR(std::remainder(g.origin_y - 7.5, 100), 0, 1e-6);
  EXPECT_LE(g.MinX(), free->geometry().MinX() + 1e-6);  // snapped outward: covers the source
  EXPECT_GE(g.MaxY(), free->geometry().MaxY() - 1e-6);
  auto cells = snapped->Read();
  ASSERT_TRUE(cells.ok());
  int64_t valid = 0;
  for (float v : cells->cells) valid += std::isnan(v) ? 0 : 1;
  EXPECT_GT(valid, cells->geometry.CellCount() / 4);  // Luxembourg fills a good part of its box
}

}  // namespace
}  // namespace tinbase
