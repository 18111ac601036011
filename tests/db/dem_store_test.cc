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
#include "tests/support/dem_checks.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::CompareSamples;
using testing::CountDifferences;
using testing::DataPath;
using testing::ExpectedBlocks;
using testing::MakeStore;
using testing::OpenRaster;
using testing::Options;
using testing::StoreTarget;
using testing::TableChecksums;
using testing::TempDir;
using testing::WriteGrid;

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
  const std::string path = StoreTarget(dir, "v2.tinbase");
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
