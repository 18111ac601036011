// Helpers of the DEM store tests (dem_store_test, dem_mosaic_test, dem_read_test): stores,
// GDAL reads to compare with, the four Vinschgau sheets of a mosaic.
#pragma once

#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/raster/gdal_raster.h"
#include "db/dem_store.h"
#include "db/store.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {

inline DemImportOptions Options(const std::string& name, int block_size = 256) {
  DemImportOptions options;
  options.name = name;
  options.block_size = block_size;
  return options;
}

inline std::unique_ptr<Store> MakeStore(const TempDir& dir, const std::string& crs,
                                        const std::string& name = "s.tinbase") {
  auto store = Store::Create(StoreTarget(dir, name), crs);
  EXPECT_TRUE(store.ok()) << store.status().ToString();
  return std::move(store).value();
}

inline GdalRaster OpenRaster(const std::string& path) {
  auto raster = GdalRaster::Open(path);
  EXPECT_TRUE(raster.ok()) << raster.status().ToString();
  return std::move(raster).value();
}

using DatasetPtr = std::unique_ptr<GDALDataset, void (*)(GDALDataset*)>;

// A Float64 GeoTIFF copy of `ds` in GDAL's memory file system (same cells, geotransform and
// nodata). GDAL's resampled RasterIO returns values in the band's own type: on an Int16 band its
// bilinear value is rounded to whole metres and on Float32 to float precision (1.2e-4 m at
// 2000 m), too coarse to check Sample to 1e-4 m; on the Float64 copy GDAL interpolates the very
// same cells in double precision. (Not the MEM driver: for a 1 x 1 window into a 1 x 1 buffer it
// copies the nearest cell and ignores the floating-point window.)
inline DatasetPtr AsFloat64(GDALDataset* ds) {
  static int serial = 0;
  const std::string path = "/vsimem/dem_store_test_" + std::to_string(++serial) + ".tif";
  const char* argv[] = {"-of", "GTiff", "-ot", "Float64", nullptr};
  GDALTranslateOptions* options = GDALTranslateOptionsNew(const_cast<char**>(argv), nullptr);
  GDALDatasetH copy = GDALTranslate(path.c_str(), GDALDataset::ToHandle(ds), options, nullptr);
  GDALTranslateOptionsFree(options);
  EXPECT_NE(copy, nullptr);
  return DatasetPtr(GDALDataset::FromHandle(copy), [](GDALDataset* d) {
    const std::string name = d->GetDescription();
    GDALClose(d);
    VSIUnlink(name.c_str());
  });
}

// GDAL's bilinear value at world (x, y): a 1 x 1 read of the one-cell window centred on the point
// in pixel space, resampled bilinearly.
inline double GdalBilinear(GDALDataset* ds, double x, double y) {
  double gt[6];
  ds->GetGeoTransform(gt);
  const double col = (x - gt[0]) / gt[1];
  const double row = (y - gt[3]) / gt[5];
  GDALRasterIOExtraArg extra;
  INIT_RASTERIO_EXTRA_ARG(extra);
  extra.eResampleAlg = GRIORA_Bilinear;
  extra.bFloatingPointWindowValidity = TRUE;
  extra.dfXOff = col - 0.5;
  extra.dfYOff = row - 0.5;
  extra.dfXSize = 1;
  extra.dfYSize = 1;
  double value = std::nan("");
  const CPLErr err = ds->GetRasterBand(1)->RasterIO(
      GF_Read, static_cast<int>(std::floor(col - 0.5)), static_cast<int>(std::floor(row - 0.5)), 1,
      1, &value, 1, 1, GDT_Float64, 0, 0, &extra);
  EXPECT_EQ(err, CE_None);
  return value;
}

inline int64_t FloorDivForTest(int64_t a, int64_t b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// Number of cells that differ (NaN equals only NaN); the first few are reported.
inline int64_t CountDifferences(const Grid& stored, const Grid& source) {
  EXPECT_EQ(stored.geometry.width, source.geometry.width);
  EXPECT_EQ(stored.geometry.height, source.geometry.height);
  EXPECT_DOUBLE_EQ(stored.geometry.origin_x, source.geometry.origin_x);
  EXPECT_DOUBLE_EQ(stored.geometry.origin_y, source.geometry.origin_y);
  EXPECT_DOUBLE_EQ(stored.geometry.cell_x, source.geometry.cell_x);
  EXPECT_DOUBLE_EQ(stored.geometry.cell_y, source.geometry.cell_y);
  if (stored.cells.size() != source.cells.size()) return -1;
  int64_t differences = 0;
  for (size_t i = 0; i < source.cells.size(); ++i) {
    const float a = stored.cells[i];
    const float b = source.cells[i];
    if ((std::isnan(a) && std::isnan(b)) || a == b) continue;
    if (++differences <= 5)
      ADD_FAILURE() << "cell " << i % source.geometry.width << ", " << i / source.geometry.width
                    << ": stored " << a << ", source " << b;
  }
  return differences;
}

// Compares Sample with GDAL's bilinear read at `count` random points whose 4 x 4 neighbourhood
// holds data, away from the border (where GDAL and we both extend edges, but differently
// documented). Returns how many points were compared.
inline int CompareSamples(DemStore& dems, const DemInfo& dem, GDALDataset* source_dataset,
                          const Grid& source, uint32_t seed, int count) {
  SCOPED_TRACE("seed " + std::to_string(seed));
  const DatasetPtr reference = AsFloat64(source_dataset);
  std::mt19937 rng(seed);
  const GridGeometry& g = source.geometry;
  std::uniform_real_distribution<double> ucol(1.0, static_cast<double>(g.width) - 2.0);
  std::uniform_real_distribution<double> urow(1.0, static_cast<double>(g.height) - 2.0);
  int compared = 0;
  double worst = 0;
  for (int attempt = 0; compared < count && attempt < count * 50; ++attempt) {
    const double fc = ucol(rng);
    const double fr = urow(rng);
    const auto c = static_cast<int64_t>(std::floor(fc));
    const auto r = static_cast<int64_t>(std::floor(fr));
    bool valid = true;
    for (int64_t rr = r - 1; rr <= r + 2 && valid; ++rr)
      for (int64_t cc = c - 1; cc <= c + 2 && valid; ++cc) valid = source.IsValid(cc, rr);
    if (!valid) continue;
    // fc, fr are in centre space; the world point is at their cell centre offsets.
    const double x = g.origin_x + (fc + 0.5) * g.cell_x;
    const double y = g.origin_y + (fr + 0.5) * g.cell_y;
    auto z = dems.Sample(dem, x, y);
    EXPECT_TRUE(z.ok()) << z.status().ToString();
    if (!z.ok()) continue;
    const double expected = GdalBilinear(reference.get(), x, y);
    // GDAL's bilinear kernel computes in float32 even on Float64 bands, so its answer carries
    // float32 round-off: 1e-4 m holds below 2048 m; above, one float32 ulp (2.4e-4 m at 4000 m)
    // is the finest GDAL can resolve.
    const double tolerance =
        std::max(1e-4, std::abs(expected) * std::numeric_limits<float>::epsilon());
    EXPECT_NEAR(*z, expected, tolerance) << "at (" << x << ", " << y << ")";
    worst = std::max(worst, std::abs(*z - expected));
    ++compared;
  }
  std::printf("%s: %d points, largest |Sample - GDAL| = %.3g m\n", dem.name.c_str(), compared,
              worst);
  return compared;
}

// Blocks that hold at least one valid cell, and their zmin/zmax, computed from the source grid.
inline std::map<std::pair<int64_t, int64_t>, std::pair<float, float>> ExpectedBlocks(
    const Grid& source, int b) {
  std::map<std::pair<int64_t, int64_t>, std::pair<float, float>> blocks;
  for (int64_t r = 0; r < source.geometry.height; ++r)
    for (int64_t c = 0; c < source.geometry.width; ++c) {
      if (!source.IsValid(c, r)) continue;
      const float v = source.At(c, r);
      auto [it, fresh] = blocks.try_emplace({c / b, r / b}, v, v);
      it->second.first = std::min(it->second.first, v);
      it->second.second = std::max(it->second.second, v);
    }
  return blocks;
}

// ---- Mosaics: several sheets of one grid in one DEM.

// Cuts `source` with gdal_translate -srcwin (col, row, width, height) into `path`.
inline void CutSheet(const std::string& source, const std::string& path, int col, int row,
                     int width, int height) {
  EnsureGdalRegistered();
  const std::vector<std::string> args = {"-of",
                                         "GTiff",
                                         "-srcwin",
                                         std::to_string(col),
                                         std::to_string(row),
                                         std::to_string(width),
                                         std::to_string(height)};
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  GDALDatasetH in = GDALOpen(source.c_str(), GA_ReadOnly);
  ASSERT_NE(in, nullptr);
  GDALTranslateOptions* options = GDALTranslateOptionsNew(argv.data(), nullptr);
  GDALDatasetH out = GDALTranslate(path.c_str(), in, options, nullptr);
  GDALTranslateOptionsFree(options);
  ASSERT_NE(out, nullptr);
  GDALClose(out);
  GDALClose(in);
}

struct SheetCut {
  const char* name;
  int col, row, width, height;
};
// elev_vinschgau is 252 x 194: four sheets overlapping by 20 columns and 10 rows.
constexpr SheetCut kVinschgauSheets[] = {{"nw", 0, 0, 140, 110},
                                         {"ne", 120, 0, 132, 110},
                                         {"sw", 0, 100, 140, 94},
                                         {"se", 120, 100, 132, 94}};

class Mosaic : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const SheetCut& s : kVinschgauSheets) {
      paths_[s.name] = dir_.Path(std::string(s.name) + ".tif");
      CutSheet(DataPath("dem/elev_vinschgau.tif"), paths_[s.name], s.col, s.row, s.width, s.height);
    }
    original_ = *OpenRaster(DataPath("dem/elev_vinschgau.tif")).Read();
  }

  TempDir dir_;
  std::map<std::string, std::string> paths_;
  Grid original_;
};

// Writes `grid` (in `crs`) as a float32 GeoTIFF with NaN nodata.
inline void WriteGrid(const std::string& path, const Grid& grid, const std::string& crs_wkt) {
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  const auto& g = grid.geometry;
  GDALDataset* ds = gtiff->Create(path.c_str(), static_cast<int>(g.width),
                                  static_cast<int>(g.height), 1, GDT_Float32, nullptr);
  ASSERT_NE(ds, nullptr);
  double gt[6] = {g.origin_x, g.cell_x, 0, g.origin_y, 0, g.cell_y};
  ds->SetGeoTransform(gt);
  OGRSpatialReference srs;
  srs.importFromWkt(crs_wkt.c_str());
  ds->SetSpatialRef(&srs);
  ds->GetRasterBand(1)->SetNoDataValue(std::nan(""));
  ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(
                GF_Write, 0, 0, static_cast<int>(g.width), static_cast<int>(g.height),
                const_cast<float*>(grid.cells.data()), static_cast<int>(g.width),
                static_cast<int>(g.height), GDT_Float32, 0, 0, nullptr),
            CE_None);
  GDALClose(ds);
}

// Level L+1 of `g` from level L the slow, obvious way: each cell the mean of the valid cells of
// the 2 x 2 below it (the grid's corner is the block anchor, as for a single-file import).
inline Grid HalveForTest(const Grid& g) {
  Grid out;
  out.geometry = g.geometry;
  out.geometry.cell_x *= 2;
  out.geometry.cell_y *= 2;
  out.geometry.width = (g.geometry.width + 1) / 2;
  out.geometry.height = (g.geometry.height + 1) / 2;
  out.cells.assign(static_cast<size_t>(out.geometry.CellCount()), std::nanf(""));
  for (int64_t r = 0; r < out.geometry.height; ++r)
    for (int64_t c = 0; c < out.geometry.width; ++c) {
      double sum = 0;
      int n = 0;
      for (int64_t rr = 2 * r; rr < std::min(2 * r + 2, g.geometry.height); ++rr)
        for (int64_t cc = 2 * c; cc < std::min(2 * c + 2, g.geometry.width); ++cc)
          if (g.IsValid(cc, rr)) {
            sum += g.At(cc, rr);
            ++n;
          }
      if (n > 0) out.cells[static_cast<size_t>(r * out.geometry.width + c)] = float(sum / n);
    }
  return out;
}

inline DemBox WholeBox(const GridGeometry& g) {
  return DemBox{g.MinX(), g.MinY(), g.MaxX(), g.MaxY()};
}

}  // namespace tinbase::testing
