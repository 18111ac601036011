// DemStore on the real DEMs: what is stored equals the source cell by cell, Sample equals GDAL's
// own bilinear read, bad input is refused with a message naming it and leaves the store as it was.
#include "db/dem_store.h"

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
#include "db/migrations.h"
#include "db/sql/connection.h"
#include "db/store.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::TableChecksums;
using testing::TempDir;

DemImportOptions Options(const std::string& name, int block_size = 256) {
  DemImportOptions options;
  options.name = name;
  options.block_size = block_size;
  return options;
}

std::unique_ptr<Store> MakeStore(const TempDir& dir, const std::string& crs,
                                 const std::string& name = "s.tinbase") {
  auto store = Store::Create(dir.Path(name), crs);
  EXPECT_TRUE(store.ok()) << store.status().ToString();
  return std::move(store).value();
}

GdalRaster OpenRaster(const std::string& path) {
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
DatasetPtr AsFloat64(GDALDataset* ds) {
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
double GdalBilinear(GDALDataset* ds, double x, double y) {
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

int64_t FloorDivForTest(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// Number of cells that differ (NaN equals only NaN); the first few are reported.
int64_t CountDifferences(const Grid& stored, const Grid& source) {
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
int CompareSamples(DemStore& dems, const DemInfo& dem, GDALDataset* source_dataset,
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
std::map<std::pair<int64_t, int64_t>, std::pair<float, float>> ExpectedBlocks(const Grid& source,
                                                                              int b) {
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

struct RealFile {
  std::string file;
  std::string store_crs;  // "" = the store adopts the file's CRS
  int block_size;
  int expected_epsg;  // the store's CRS afterwards
};

void PrintTo(const RealFile& p, std::ostream* os) {
  *os << p.file << " (store CRS '" << p.store_crs << "', block " << p.block_size << ")";
}

class ImportRealFile : public ::testing::TestWithParam<RealFile> {};

TEST_P(ImportRealFile, StoresTheSourceCellByCellAndSamplesLikeGdal) {
  const RealFile& p = GetParam();
  TempDir dir;
  auto store = MakeStore(dir, p.store_crs);
  DemStore dems(*store);
  DemImportOptions options;
  options.block_size = p.block_size;
  auto report = dems.Import({DataPath(p.file)}, options);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_FALSE(report->warped);

  const GdalRaster raster = OpenRaster(DataPath(p.file));
  auto source = raster.Read();
  ASSERT_TRUE(source.ok()) << source.status().ToString();
  EXPECT_EQ(report->cells, source->geometry.CellCount());

  auto found = dems.Find(std::filesystem::path(p.file).stem().string());
  ASSERT_TRUE(found.ok()) << found.status().ToString();
  EXPECT_EQ(found->id, report->dem.id);
  EXPECT_EQ(found->block_size, p.block_size);
  EXPECT_EQ(found->nodata.has_value(), raster.nodata().has_value());
  auto crs = store->GetCrs();
  ASSERT_TRUE(crs.ok() && crs->has_value());
  EXPECT_EQ((*crs)->Epsg().value_or(0), p.expected_epsg);

  auto stored = dems.ReadGrid(*found);
  ASSERT_TRUE(stored.ok()) << stored.status().ToString();
  EXPECT_EQ(CountDifferences(*stored, *source), 0);

  // All-nodata blocks are left out; zmin/zmax are those of the block's valid cells.
  const auto expected = ExpectedBlocks(*source, p.block_size);
  auto rows = store->db().Prepare(
      "SELECT bx, by, zmin, zmax, length(data) FROM dem_blocks WHERE dem = ? AND level = 0");
  ASSERT_TRUE(rows.ok());
  (*rows)->Bind(1, found->id);
  int64_t count = 0;
  int64_t bytes = 0;
  while (*(*rows)->Step()) {
    const auto key = std::make_pair((*rows)->ColumnInt(0), (*rows)->ColumnInt(1));
    auto it = expected.find(key);
    ASSERT_NE(it, expected.end()) << "block " << key.first << ", " << key.second;
    EXPECT_EQ((*rows)->ColumnDouble(2), it->second.first);
    EXPECT_EQ((*rows)->ColumnDouble(3), it->second.second);
    bytes += (*rows)->ColumnInt(4);
    ++count;
  }
  EXPECT_EQ(count, static_cast<int64_t>(expected.size()));
  EXPECT_EQ(report->blocks_written, count);
  EXPECT_EQ(report->bytes_stored, bytes);

  EXPECT_EQ(CompareSamples(dems, *found, raster.dataset(), *source, 20240611, 300), 300);
}

INSTANTIATE_TEST_SUITE_P(RealFiles, ImportRealFile,
                         ::testing::Values(RealFile{"dem/elev_vinschgau.tif", "", 64, 32632},
                                           RealFile{"geology/hamersley/dtm_rp.tif", "", 64, 28350},
                                           RealFile{"dem/elev.tif", "EPSG:4326", 16, 4326},
                                           RealFile{"dem/N43E007.hgt", "EPSG:4326", 256, 4326}),
                         [](const auto& info) {
                           std::string name =
                               std::filesystem::path(info.param.file).stem().string();
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

TEST(DemStore, GeographicSourceIntoStoreWithoutCrsIsWarpedToItsUtmZone) {
  TempDir dir;
  auto store = MakeStore(dir, "");
  DemStore dems(*store);
  auto report = dems.Import({DataPath("dem/N43E007.hgt")}, {});
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_TRUE(report->warped);
  auto crs = store->GetCrs();
  ASSERT_TRUE(crs.ok() && crs->has_value());
  EXPECT_EQ((*crs)->Epsg().value_or(0), 32632);  // 7.5 E, 43.5 N: UTM zone 32 north

  auto utm = Crs::FromUserInput("EPSG:32632");
  ASSERT_TRUE(utm.ok());
  auto warped = OpenRaster(DataPath("dem/N43E007.hgt")).WarpTo(*utm);
  ASSERT_TRUE(warped.ok()) << warped.status().ToString();
  const GridGeometry& g = warped->geometry();
  EXPECT_EQ(g.cell_x, -g.cell_y);  // square cells
  EXPECT_NEAR(g.cell_x, 75, 10);   // 3 arc-seconds is about 92 m N-S, 67 m E-W at 43.5 N

  auto dem = dems.Find("N43E007");
  ASSERT_TRUE(dem.ok());
  EXPECT_TRUE(Crs::FromWkt(dem->crs_wkt)->IsSame(*utm));
  auto stored = dems.ReadGrid(*dem);
  auto source = warped->Read();
  ASSERT_TRUE(stored.ok() && source.ok());
  EXPECT_EQ(CountDifferences(*stored, *source), 0);
  EXPECT_EQ(CompareSamples(dems, *dem, warped->dataset(), *source, 7, 300), 300);
}

TEST(DemStore, ProjectedSourceIntoStoreOfAnotherCrsIsWarped) {
  TempDir dir;
  auto store = MakeStore(dir, "EPSG:4326");
  DemStore dems(*store);
  auto report = dems.Import({DataPath("dem/elev_vinschgau.tif")}, {});
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_TRUE(report->warped);
  EXPECT_TRUE(Crs::FromWkt(report->dem.crs_wkt)->IsGeographic());
  EXPECT_EQ(report->dem.geometry.cell_x, -report->dem.geometry.cell_y);
  // 250 m cells at 46.7 N are about 0.0027 degrees of longitude and 0.0022 of latitude.
  EXPECT_GT(report->dem.geometry.cell_x, 0.0015);
  EXPECT_LT(report->dem.geometry.cell_x, 0.004);
}

TEST(DemStore, SampleOutsideOrOnNodataSaysWhereAndChangesNothing) {
  TempDir dir;
  auto store = MakeStore(dir, "EPSG:4326");
  DemStore dems(*store);
  ASSERT_TRUE(dems.Import({DataPath("dem/elev.tif")}, Options("lux", 32)).ok());
  auto dem = dems.Find("lux");
  ASSERT_TRUE(dem.ok());
  const auto before = TableChecksums(store->path());

  auto outside = dems.Sample(*dem, dem->geometry.MaxX() + 0.5, dem->geometry.MaxY());
  ASSERT_FALSE(outside.ok());
  EXPECT_EQ(outside.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(outside.status().message().find("is outside DEM 'lux'"), std::string::npos)
      << outside.status().message();
  EXPECT_EQ(outside.status().message().find("point ("), 0u) << outside.status().message();

  // The top-left corner of elev.tif lies outside Luxembourg: nodata.
  const Grid source = *OpenRaster(DataPath("dem/elev.tif")).Read();
  ASSERT_FALSE(source.IsValid(0, 0) || source.IsValid(1, 0) || source.IsValid(0, 1) ||
               source.IsValid(1, 1));
  const double x = source.geometry.CellCenterX(0) + 0.3 * source.geometry.cell_x;
  const double y = source.geometry.CellCenterY(0) + 0.6 * source.geometry.cell_y;
  auto nodata = dems.Sample(*dem, x, y);
  ASSERT_FALSE(nodata.ok());
  EXPECT_EQ(nodata.status().code(), StatusCode::kNotFound);
  EXPECT_NE(nodata.status().message().find("no data at ("), std::string::npos);
  EXPECT_NE(nodata.status().message().find(") in DEM 'lux'"), std::string::npos);

  auto nan = dems.Sample(*dem, std::nan(""), y);
  EXPECT_EQ(nan.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(TableChecksums(store->path()), before);
}

TEST(DemStore, DamagedBlockIsReportedAsCorruptionNamingTheBlock) {
  TempDir dir;
  auto store = MakeStore(dir, "");
  DemStore dems(*store);
  ASSERT_TRUE(dems.Import({DataPath("dem/elev_vinschgau.tif")}, Options("", 64)).ok());
  auto dem = dems.Find("elev_vinschgau");
  ASSERT_TRUE(dem.ok());
  ASSERT_TRUE(store->db()
                  .Exec("UPDATE dem_blocks SET data = substr(data, 1, length(data) - 9) || "
                        "x'000000000000000000' WHERE bx = 1 AND by = 1")
                  .ok());
  const double x = dem->geometry.CellCenterX(64 + 10);
  const double y = dem->geometry.CellCenterY(64 + 20);
  DemStore fresh(*store);  // no cached copy of the block
  auto z = fresh.Sample(*dem, x, y);
  ASSERT_FALSE(z.ok());
  EXPECT_EQ(z.status().code(), StatusCode::kCorruption);
  EXPECT_NE(z.status().message().find("DEM 'elev_vinschgau', level 0 block (1, 1)"),
            std::string::npos)
      << z.status().message();
  EXPECT_FALSE(fresh.ReadGrid(*dem).ok());
}

// Writes a small float32 GeoTIFF; `crs` and `geotransform` may be left out on purpose.
void WriteTiff(const std::string& path, const std::string& crs, const double* geotransform,
               int size = 16) {
  EnsureGdalRegistered();
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  ASSERT_NE(gtiff, nullptr);
  GDALDataset* ds = gtiff->Create(path.c_str(), size, size, 1, GDT_Float32, nullptr);
  ASSERT_NE(ds, nullptr);
  std::vector<float> cells(static_cast<size_t>(size * size));
  for (size_t i = 0; i < cells.size(); ++i) cells[i] = 100.0f + static_cast<float>(i);
  ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, size, size, cells.data(), size, size,
                                           GDT_Float32, 0, 0, nullptr),
            CE_None);
  if (geotransform != nullptr) ds->SetGeoTransform(const_cast<double*>(geotransform));
  if (!crs.empty()) {
    OGRSpatialReference srs;
    srs.SetFromUserInput(crs.c_str());
    ds->SetSpatialRef(&srs);
  }
  GDALClose(ds);
}

class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = MakeStore(dir_, "");
    dems_ = std::make_unique<DemStore>(*store_);
    ASSERT_TRUE(dems_->Import({DataPath("dem/elev.tif")}, Options("lux")).ok());
    before_ = TableChecksums(store_->path());
    ASSERT_EQ(before_.count("<error>"), 0u);
  }
  // Import must fail with `code` and a message holding `needle`; the store stays as it was.
  void ExpectRefused(const std::vector<std::string>& files, StatusCode code,
                     const std::string& needle, DemImportOptions options = {}) {
    auto report = dems_->Import(files, options);
    ASSERT_FALSE(report.ok());
    EXPECT_EQ(report.status().code(), code) << report.status().ToString();
    EXPECT_NE(report.status().message().find(needle), std::string::npos)
        << report.status().message() << "\n  should contain: " << needle;
    EXPECT_EQ(TableChecksums(store_->path()), before_);
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
  std::unique_ptr<DemStore> dems_;
  std::map<std::string, std::string> before_;
};

TEST_F(BadInput, MissingFile) {
  const std::string path = dir_.Path("nowhere.tif");
  ExpectRefused({path}, StatusCode::kNotFound, path + ": no such file");
}

TEST_F(BadInput, TextFile) {
  const std::string path = dir_.Path("notes.tif");
  std::ofstream(path) << "these are notes, not elevations\n";
  ExpectRefused({path}, StatusCode::kInvalidArgument, path + ": not a raster GDAL can read");
}

TEST_F(BadInput, GeoTiffWithoutCrs) {
  const std::string path = dir_.Path("nocrs.tif");
  const double gt[6] = {500000, 30, 0, 5200000, 0, -30};
  WriteTiff(path, "", gt);
  ExpectRefused({path}, StatusCode::kInvalidArgument, path + ": raster has no CRS");
}

TEST_F(BadInput, GeoTiffWithoutGeotransform) {
  const std::string path = dir_.Path("nogt.tif");
  WriteTiff(path, "EPSG:32632", nullptr);
  ExpectRefused({path}, StatusCode::kInvalidArgument, path + ": raster has no geotransform");
}

TEST_F(BadInput, RotatedGeotransform) {
  const std::string path = dir_.Path("rotated.tif");
  const double gt[6] = {500000, 30, 5, 5200000, 5, -30};
  WriteTiff(path, "EPSG:32632", gt);
  ExpectRefused({path}, StatusCode::kInvalidArgument, path + ": rotated geotransform");
}

TEST_F(BadInput, BlockSizeNotAPowerOfTwo) {
  ExpectRefused({DataPath("dem/elev_vinschgau.tif")}, StatusCode::kInvalidArgument,
                "block size 100 is not a power of two", Options("", 100));
}

// The first `keep` bytes of a real GeoTIFF: the header and directory survive, the cells do not.
TEST_F(BadInput, TruncatedGeoTiff) {
  const std::string source = DataPath("dem/elev_vinschgau.tif");
  const std::string path = dir_.Path("truncated.tif");
  std::filesystem::copy_file(source, path);
  std::filesystem::resize_file(path, std::filesystem::file_size(source) / 2);
  ExpectRefused({path}, StatusCode::kIOError, path + ": cannot read cells");
}

// Garbage over the compressed cells of a real GeoTIFF, the header intact.
TEST_F(BadInput, CorruptCellsInGeoTiff) {
  const std::string path = dir_.Path("corrupt.tif");
  const char* argv[] = {"-co", "COMPRESS=DEFLATE", nullptr};
  GDALTranslateOptions* options = GDALTranslateOptionsNew(const_cast<char**>(argv), nullptr);
  GDALDatasetH copy =
      GDALTranslate(path.c_str(), GDALOpen(DataPath("dem/elev_vinschgau.tif").c_str(), GA_ReadOnly),
                    options, nullptr);
  GDALTranslateOptionsFree(options);
  ASSERT_NE(copy, nullptr);
  GDALClose(copy);
  const auto size = std::filesystem::file_size(path);
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  file.seekp(static_cast<std::streamoff>(size / 2));
  for (int i = 0; i < 4096; ++i) file.put(static_cast<char>(i * 131 % 251));
  file.close();
  ExpectRefused({path}, StatusCode::kIOError, path + ": cannot read cells");
}

TEST_F(BadInput, UnknownCrs) {
  const std::string path = dir_.Path("local.tif");
  const double gt[6] = {500000, 30, 0, 5200000, 0, -30};
  WriteTiff(
      path,
      R"(LOCAL_CS["mine site grid",UNIT["metre",1],AXIS["Easting",EAST],AXIS["Northing",NORTH]])",
      gt);
  ExpectRefused({path}, StatusCode::kInvalidArgument, path + ": cannot warp onto EPSG:32632");
}

TEST_F(BadInput, NoFiles) { ExpectRefused({}, StatusCode::kInvalidArgument, "no files"); }

TEST_F(BadInput, SecondOfTwoFilesIsBad) {
  const std::string path = dir_.Path("notes.txt");
  std::ofstream(path) << "x y z\n";
  ExpectRefused({DataPath("dem/elev_vinschgau.tif"), path}, StatusCode::kInvalidArgument, path);
}

// The second sheet is readable but does not line up with the first: the failure comes after the
// store's CRS was set and the DEM row written, inside the transaction, which must roll back.
TEST(DemStore, FailureAfterWritingRollsEverythingBack) {
  TempDir dir;
  auto store = MakeStore(dir, "");
  const auto before = TableChecksums(store->path());
  const std::string shifted = dir.Path("shifted.tif");
  // elev_vinschgau's grid has 250 m cells; an origin 100 m off does not lie on it.
  const double gt[6] = {600100, 250, 0, 5190000, 0, -250};
  WriteTiff(shifted, "EPSG:32632", gt);
  DemStore dems(*store);
  auto report = dems.Import({DataPath("dem/elev_vinschgau.tif"), shifted}, Options("v"));
  ASSERT_FALSE(report.ok());
  EXPECT_NE(report.status().message().find(shifted + ": origin"), std::string::npos)
      << report.status().message();
  EXPECT_NE(report.status().message().find("does not lie on the grid of DEM 'v'"),
            std::string::npos);
  EXPECT_EQ(TableChecksums(store->path()), before);
  EXPECT_FALSE(store->GetCrs()->has_value());
  EXPECT_EQ(dems.Find("v").status().code(), StatusCode::kNotFound);
}

// A store of schema version 2 kept the block anchor only in sources[0]; migration 0003 moves it
// into block_col0 / block_row0 (rounded to whole cells), and a DEM without sources gets 0, 0.
TEST(DemStore, Migration0003FillsTheBlockAnchorFromTheFirstSource) {
  TempDir dir;
  const std::string path = dir.Path("v2.tinbase");
  {
    auto db = Connection::Open(path, Connection::Mode::kCreate);
    ASSERT_TRUE(db.ok());
    ASSERT_TRUE(
        (*db)->Exec("PRAGMA application_id = " + std::to_string(kTinbaseApplicationId)).ok());
    ASSERT_TRUE(MigrateStore(**db, 2).ok());
    // Grid corner (1000, 9000), 10 m cells: the first sheet's origin (1500.0000001, 8200) is
    // 50 columns east and 80 rows south of it.
    ASSERT_TRUE((*db)
                    ->Exec("INSERT INTO dems(id, name, crs_wkt, origin_x, origin_y, cell_x, "
                           "cell_y, width, height, block_size, levels, sources) VALUES "
                           "(1, 'a', '', 1000, 9000, 10, -10, 100, 100, 32, 3, "
                           "'[{\"origin_x\": 1500.0000001, \"origin_y\": 8200}, "
                           "{\"origin_x\": 1000, \"origin_y\": 9000}]'), "
                           "(2, 'b', '', 0, 0, 1, -1, 5, 5, 32, 1, '[]')")
                    .ok());
  }
  auto store = Store::Open(path);
  ASSERT_TRUE(store.ok()) << store.status().ToString();
  DemStore dems(**store);
  auto a = dems.Find("a");
  ASSERT_TRUE(a.ok()) << a.status().ToString();
  EXPECT_EQ(a->block_col0, 50);
  EXPECT_EQ(a->block_row0, 80);
  auto b = dems.Find("b");
  ASSERT_TRUE(b.ok()) << b.status().ToString();
  EXPECT_EQ(b->block_col0, 0);
  EXPECT_EQ(b->block_row0, 0);
}

// ---- Mosaics: several sheets of one grid in one DEM.

// Cuts `source` with gdal_translate -srcwin (col, row, width, height) into `path`.
void CutSheet(const std::string& source, const std::string& path, int col, int row, int width,
              int height) {
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

TEST_F(Mosaic, FourSheetsInOneImportRebuildTheOriginal) {
  auto store = MakeStore(dir_, "");
  DemStore dems(*store);
  auto report = dems.Import({paths_["nw"], paths_["ne"], paths_["sw"], paths_["se"]},
                            Options("vinschgau", 64));
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  auto dem = dems.Find("vinschgau");
  ASSERT_TRUE(dem.ok());
  auto stored = dems.ReadGrid(*dem);
  ASSERT_TRUE(stored.ok()) << stored.status().ToString();
  EXPECT_EQ(CountDifferences(*stored, original_), 0);
  EXPECT_EQ(report->blocks_written, static_cast<int64_t>(ExpectedBlocks(original_, 64).size()));
}

// Importing the sheets one by one from the south-east grows the DEM west and north; blocks stay
// anchored at the first sheet's origin, so each import writes only the blocks its sheet touches.
TEST_F(Mosaic, SheetsAddedOneByOneGrowTheDemAndWriteOnlyTouchedBlocks) {
  auto store = MakeStore(dir_, "");
  DemStore dems(*store);
  constexpr int kBlock = 32;
  const SheetCut& first = kVinschgauSheets[3];  // se
  for (int i : {3, 1, 2, 0}) {
    const SheetCut& s = kVinschgauSheets[i];
    SCOPED_TRACE(s.name);
    auto report = dems.Import({paths_[s.name]}, Options("grown", kBlock));
    ASSERT_TRUE(report.ok()) << report.status().ToString();
    // Blocks are counted from the first sheet's corner in the original's columns and rows.
    std::set<std::pair<int64_t, int64_t>> touched;
    for (int r = s.row; r < s.row + s.height; ++r)
      for (int c = s.col; c < s.col + s.width; ++c)
        if (original_.IsValid(c, r))
          touched.emplace(FloorDivForTest(c - first.col, kBlock),
                          FloorDivForTest(r - first.row, kBlock));
    EXPECT_EQ(report->blocks_written, static_cast<int64_t>(touched.size()));
    EXPECT_EQ(report->dem.block_col0 + report->dem.geometry.origin_x / 250,
              first.col + original_.geometry.origin_x / 250);
  }
  auto dem = dems.Find("grown");
  ASSERT_TRUE(dem.ok());
  auto stored = dems.ReadGrid(*dem);
  ASSERT_TRUE(stored.ok()) << stored.status().ToString();
  EXPECT_EQ(CountDifferences(*stored, original_), 0);
  EXPECT_EQ(dem->block_col0, first.col);
  EXPECT_EQ(dem->block_row0, first.row);
  auto sources = store->db().Prepare("SELECT json_array_length(sources) FROM dems");
  ASSERT_TRUE(sources.ok() && *(*sources)->Step());
  EXPECT_EQ((*sources)->ColumnInt(0), 4);
  EXPECT_EQ(CompareSamples(dems, *dem, OpenRaster(DataPath("dem/elev_vinschgau.tif")).dataset(),
                           original_, 99, 200),
            200);
}

// Writes `grid` (in `crs`) as a float32 GeoTIFF with NaN nodata.
void WriteGrid(const std::string& path, const Grid& grid, const std::string& crs_wkt) {
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

// Samples served from the cache before an import that rewrites the blocks are not served after
// it: in the importing DemStore at once, in another connection (as another process would be)
// after its next Find.
TEST_F(Mosaic, ImportInvalidatesCachedBlocks) {
  auto store = MakeStore(dir_, "");
  DemStore dems(*store);
  ASSERT_TRUE(dems.Import({paths_["ne"]}, Options("v", 32)).ok());
  auto other_store = Store::Open(store->path(), Store::Access::kReadOnly);
  ASSERT_TRUE(other_store.ok());
  DemStore other(**other_store);
  auto dem = dems.Find("v");
  ASSERT_TRUE(dem.ok());
  auto other_dem = other.Find("v");
  ASSERT_TRUE(other_dem.ok());
  // A point of the north-east sheet with data around it.
  const GridGeometry& g = dem->geometry;
  double x = 0, y = 0;
  double before = 0;
  bool found = false;
  for (int64_t r = 5; r < g.height - 5 && !found; ++r)
    for (int64_t c = 5; c < g.width - 5 && !found; ++c) {
      x = g.CellCenterX(c) + 0.25 * g.cell_x;
      y = g.CellCenterY(r);
      auto z = dems.Sample(*dem, x, y);
      found = z.ok();
      if (found) before = *z;
    }
  ASSERT_TRUE(found);
  ASSERT_EQ(*other.Sample(*other_dem, x, y), before);  // warm in both
  Grid raised = *OpenRaster(paths_["ne"]).Read();
  for (float& v : raised.cells) v += 1000;
  const std::string raised_path = dir_.Path("ne_raised.tif");
  WriteGrid(raised_path, raised, raised.crs_wkt);
  ASSERT_TRUE(dems.Import({raised_path}, Options("v", 32)).ok());
  auto after = dems.Sample(*dem, x, y);
  ASSERT_TRUE(after.ok());
  EXPECT_NEAR(*after, before + 1000, 1e-3);
  other_dem = other.Find("v");
  ASSERT_TRUE(other_dem.ok());
  auto other_after = other.Sample(*other_dem, x, y);
  ASSERT_TRUE(other_after.ok());
  EXPECT_EQ(*other_after, *after);
}

TEST_F(Mosaic, LaterSheetsWinUnlessKeepFirst) {
  // The north-east sheet raised by 1000 m: in the overlap its cells tell which sheet won.
  Grid raised = *OpenRaster(paths_["ne"]).Read();
  for (float& v : raised.cells) v += 1000;
  const std::string raised_path = dir_.Path("ne_raised.tif");
  WriteGrid(raised_path, raised, raised.crs_wkt);
  const SheetCut& nw = kVinschgauSheets[0];
  const SheetCut& ne = kVinschgauSheets[1];
  for (bool keep_first : {false, true}) {
    SCOPED_TRACE(keep_first ? "keep_first" : "later wins");
    TempDir dir;
    auto store = MakeStore(dir, "");
    DemStore dems(*store);
    DemImportOptions options = Options("m", 64);
    options.keep_first = keep_first;
    auto report = dems.Import({paths_["nw"], raised_path}, options);
    ASSERT_TRUE(report.ok()) << report.status().ToString();
    auto grid = dems.ReadGrid(report->dem);
    ASSERT_TRUE(grid.ok());
    int64_t checked = 0;
    for (int r = 0; r < nw.height; ++r)
      for (int c = 0; c < ne.col + ne.width; ++c) {
        if (!original_.IsValid(c, r)) continue;
        const bool in_nw = c < nw.col + nw.width;
        const bool in_ne = c >= ne.col;
        const float expected = original_.At(c, r) + ((in_ne && (!in_nw || !keep_first)) ? 1000 : 0);
        ASSERT_EQ(grid->At(c, r), expected) << c << ", " << r;
        ++checked;
      }
    EXPECT_GT(checked, 20000);
  }
}

TEST_F(Mosaic, SheetWarpedForAnExistingDemLandsOnItsGrid) {
  auto store = MakeStore(dir_, "EPSG:4326");
  DemStore dems(*store);
  auto first = dems.Import({paths_["nw"]}, Options("geo", 64));
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  auto second = dems.Import({paths_["se"]}, Options("geo", 64));
  ASSERT_TRUE(second.ok()) << second.status().ToString();
  EXPECT_TRUE(second->warped);
  const GridGeometry& a = first->dem.geometry;
  const GridGeometry& b = second->dem.geometry;
  EXPECT_EQ(a.cell_x, b.cell_x);
  EXPECT_GT(b.width, a.width);
  EXPECT_GT(b.height, a.height);
  EXPECT_NEAR(std::remainder((b.origin_x - a.origin_x) / a.cell_x, 1.0), 0, 1e-6);
  // The south-east corner of the Vinschgau lies in the second sheet only; it has data.
  const double lon = b.MaxX() - 20 * b.cell_x;
  const double lat = b.MinY() - 20 * b.cell_y;
  auto z = dems.Sample(second->dem, lon, lat);
  EXPECT_TRUE(z.ok()) << z.status().ToString();
}

// ---- Overview levels, windows, blocks and clips.

// Level L+1 of `g` from level L the slow, obvious way: each cell the mean of the valid cells of
// the 2 x 2 below it (the grid's corner is the block anchor, as for a single-file import).
Grid HalveForTest(const Grid& g) {
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

DemBox WholeBox(const GridGeometry& g) { return DemBox{g.MinX(), g.MinY(), g.MaxX(), g.MaxY()}; }

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

// Sheets added one at a time keep the overviews equal to those computed over the whole mosaic
// at once, while each import recomputes only the overview blocks above what it wrote.
TEST_F(Mosaic, OverviewsStayUpToDateAsSheetsAreAdded) {
  auto store = MakeStore(dir_, "");
  DemStore dems(*store);
  // A first sheet of one 16 x 16 block has one level; the next ones add levels as well as blocks.
  const std::string tiny = dir_.Path("tiny.tif");
  CutSheet(DataPath("dem/elev_vinschgau.tif"), tiny, 130, 110, 16, 16);
  const std::vector<std::string> order = {tiny, paths_["se"], paths_["ne"], paths_["sw"],
                                          paths_["nw"]};
  int64_t total_overview_blocks = 0;
  int64_t last_overview_blocks = 0;
  for (const std::string& path : order) {
    auto report = dems.Import({path}, Options("step", 16));
    ASSERT_TRUE(report.ok()) << report.status().ToString();
    if (path == tiny) {
      EXPECT_EQ(report->dem.levels, 1);
    }
    last_overview_blocks = report->overview_blocks_written;
  }
  auto once = dems.Import(order, Options("once", 16));
  ASSERT_TRUE(once.ok()) << once.status().ToString();
  total_overview_blocks = once->overview_blocks_written;
  EXPECT_LT(last_overview_blocks, total_overview_blocks);
  auto step = dems.Find("step");
  ASSERT_TRUE(step.ok());
  ASSERT_EQ(step->levels, once->dem.levels);
  EXPECT_GE(step->levels, 4);
  for (int level = 0; level < step->levels; ++level) {
    SCOPED_TRACE("level " + std::to_string(level));
    auto a = dems.ReadWindow(*step, WholeBox(step->geometry), level);
    auto b = dems.ReadWindow(once->dem, WholeBox(once->dem.geometry), level);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(CountDifferences(*a, *b), 0);
  }
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

// ---- Atomicity of imports: an error after any block write, and kill -9 mid-import.

// Block writes (level 0 and overviews) that importing `files` into `name` makes on `store`.
int64_t CountBlockWrites(Store& store, const std::vector<std::string>& files,
                         const std::string& name) {
  int64_t writes = 0;
  DemImportOptions options = Options(name, 32);
  options.after_block_write = [&](int64_t n) {
    writes = n;
    return Status::Ok();
  };
  EXPECT_TRUE(DemStore(store).Import(files, options).ok());
  return writes;
}

// The failure hook fails the import after block write k, for k from the first write to the last
// (every few, to stay quick), both creating a DEM and extending one with overviews: the import
// returns the error, the tables are as before, the store checks clean and reads as before.
TEST_F(Mosaic, ErrorAfterAnyBlockWriteLeavesTheStoreAsItWas) {
  const std::vector<std::string> first = {paths_["nw"], paths_["ne"]};
  const std::vector<std::string> second = {paths_["sw"], paths_["se"]};
  for (const bool extend : {false, true}) {
    SCOPED_TRACE(extend ? "extending a DEM" : "creating a DEM");
    TempDir dir;
    auto counting = MakeStore(dir, "", "count.tinbase");
    if (extend) CountBlockWrites(*counting, first, "v");
    const int64_t total = CountBlockWrites(*counting, extend ? second : first, "v");
    ASSERT_GT(total, 10);

    auto store = MakeStore(dir, "");
    DemStore dems(*store);
    if (extend) {
      ASSERT_TRUE(dems.Import(first, Options("v", 32)).ok());
    }
    const auto before = TableChecksums(store->path());
    std::optional<Grid> grid_before;
    if (extend) grid_before = *dems.ReadGrid(*dems.Find("v"));
    std::vector<int64_t> failing_writes;
    for (int64_t k = 1; k < total; k += std::max<int64_t>(1, total / 12))
      failing_writes.push_back(k);
    failing_writes.push_back(total);
    for (const int64_t k : failing_writes) {
      SCOPED_TRACE("failing after block write " + std::to_string(k) + " of " +
                   std::to_string(total));
      DemImportOptions options = Options("v", 32);
      options.after_block_write = [k](int64_t n) {
        return n == k ? Status::IOError("injected failure") : Status::Ok();
      };
      auto report = dems.Import(extend ? second : first, options);
      ASSERT_FALSE(report.ok());
      EXPECT_NE(report.status().message().find("injected failure"), std::string::npos);
      EXPECT_EQ(TableChecksums(store->path()), before);
      testing::ExpectStoreIntact(*store, /*full=*/true);
      if (extend) {
        auto dem = dems.Find("v");
        ASSERT_TRUE(dem.ok());
        EXPECT_EQ(CountDifferences(*dems.ReadGrid(*dem), *grid_before), 0);
      } else {
        EXPECT_EQ(dems.Find("v").status().code(), StatusCode::kNotFound);
      }
      if (HasFailure()) return;
    }
  }
}

// A child process imports two versions of the same sheet over each other, endlessly, and is
// killed with SIGKILL at random moments: afterwards the store checks clean and the DEM is one
// version or the other in every cell, never a mix of a half-written import.
TEST_F(Mosaic, KillNineMidImportLeavesWholeImportsOnly) {
  Grid raised = original_;
  for (float& z : raised.cells) z += 100;
  const std::string raised_path = dir_.Path("raised.tif");
  WriteGrid(raised_path, raised, original_.crs_wkt);
  const std::string original_path = DataPath("dem/elev_vinschgau.tif");
  auto store = MakeStore(dir_, "");
  ASSERT_TRUE(DemStore(*store).Import({original_path}, Options("v", 32)).ok());
  const std::string path = store->path();
  store.reset();

  std::mt19937 rng(20261122);
  std::uniform_int_distribution<int> delay_ms(0, 40);
  std::set<std::string> seen;
  for (int round = 0; round < 12; ++round) {
    int done[2];  // the child writes a byte after each whole import
    ASSERT_EQ(pipe(done), 0);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      close(done[0]);
      auto s = Store::Open(path);
      if (!s.ok()) _exit(2);
      DemStore dems(**s);
      for (int i = 0;; ++i) {
        if (!dems.Import({i % 2 ? original_path : raised_path}, Options("v", 32)).ok()) _exit(3);
        if (write(done[1], "x", 1) != 1) _exit(4);
      }
    }
    close(done[1]);
    // Kill during the import after the first (raised) or second (original) one is whole, at a
    // random moment of it: timing alone would depend on how loaded the machine is.
    for (int whole = 0; whole < 1 + round % 2; ++whole) {
      char byte = 0;
      ASSERT_EQ(read(done[0], &byte, 1), 1) << "the importing child died";
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms(rng)));
    ASSERT_EQ(kill(child, SIGKILL), 0);
    close(done[0]);
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the importing child stopped by itself: " << status;

    auto reopened = Store::Open(path);
    ASSERT_TRUE(reopened.ok()) << reopened.status().ToString();
    testing::ExpectStoreIntact(**reopened, /*full=*/true);
    DemStore dems(**reopened);
    auto dem = dems.Find("v");
    ASSERT_TRUE(dem.ok());
    auto grid = dems.ReadGrid(*dem);
    ASSERT_TRUE(grid.ok()) << grid.status().ToString();
    const auto differing = [&](const Grid& expected) {
      int64_t n = 0;
      for (size_t i = 0; i < expected.cells.size(); ++i) {
        const float a = grid->cells[i], b = expected.cells[i];
        n += !(a == b || (std::isnan(a) && std::isnan(b)));
      }
      return n;
    };
    ASSERT_EQ(grid->cells.size(), original_.cells.size());
    const int64_t as_original = differing(original_);
    const int64_t as_raised = differing(raised);
    EXPECT_TRUE(as_original == 0 || as_raised == 0)
        << "round " << round << ": " << as_original << " cells differ from the original and "
        << as_raised << " from the raised sheet";
    seen.insert(as_original == 0 ? "original" : "raised");
    if (HasFailure()) break;
  }
  EXPECT_EQ(seen.size(), 2u) << "the kills should land after both kinds of import";
}

// NaN cells in a raster that declares no nodata value are nodata all the same: sampled as
// "no data", read back as NaN, and a block holding nothing else is not stored.
TEST(DemStore, NaNCellsWithoutDeclaredNodataAreNodata) {
  EnsureGdalRegistered();
  TempDir dir;
  Grid grid;
  grid.geometry = GridGeometry{500000, 5200000, 10, -10, 64, 64};
  grid.cells.resize(64 * 64);
  for (int r = 0; r < 64; ++r)
    for (int c = 0; c < 64; ++c)
      grid.cells[r * 64 + c] = (r < 32 && c < 32) || (r == 40 && c == 50)
                                   ? std::numeric_limits<float>::quiet_NaN()
                                   : static_cast<float>(100 + r + c);
  const std::string path = dir.Path("nan.tif");
  OGRSpatialReference srs;
  srs.importFromEPSG(32632);
  char* wkt = nullptr;
  srs.exportToWkt(&wkt);
  WriteGrid(path, grid, wkt);
  CPLFree(wkt);
  {
    GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_UPDATE);
    ASSERT_NE(ds, nullptr);
    ds->GetRasterBand(1)->DeleteNoDataValue();
    int has_nodata = 1;
    ds->GetRasterBand(1)->GetNoDataValue(&has_nodata);
    EXPECT_FALSE(has_nodata);
    GDALClose(ds);
  }
  auto store = MakeStore(dir, "");
  DemStore dems(*store);
  auto report = dems.Import({path}, Options("nan", 32));
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->blocks_written, 3);  // the north-west block is all NaN
  auto stored = dems.ReadGrid(report->dem);
  ASSERT_TRUE(stored.ok());
  EXPECT_EQ(CountDifferences(*stored, grid), 0);
  const double x = grid.geometry.CellCenterX(50), y = grid.geometry.CellCenterY(40);
  auto z = dems.Sample(report->dem, x, y, DemSampling::kNearest);
  EXPECT_EQ(z.status().code(), StatusCode::kNotFound) << z.status().ToString();
  EXPECT_NE(z.status().message().find("no data"), std::string::npos) << z.status().message();
}

}  // namespace
}  // namespace tinbase
