// Issue 29 as tests: the command line tried by a hostile but fair user. Each case ends in one
// line "tinbase: <what is really wrong>" on stderr, a non-zero exit and the store unchanged, or
// (where the input is usable after all) in a store that `check --full` passes. No case aborts,
// hangs, or exits 0 leaving a store that breaks an invariant.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/raster/gdal_raster.h"
#include "db/sql/connection.h"
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

// A command that must fail with one line naming `expected`, when there is no store to compare.
void ExpectOneLineError(const CliResult& r, const std::string& expected) {
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find(expected), std::string::npos) << "stderr: " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line expected: " << r.err;
  EXPECT_EQ(r.err.rfind("tinbase: ", 0), 0u) << r.err;
}

// Root passes every permission check, so permission cases run the CLI as the unprivileged user
// "nobody" when the tests run as root; as any other user they run as that user.
std::string AsUnprivileged() {
  return ::geteuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups" : "";
}

// A shell word that is `format` as printf(1) writes it (for bytes a test cannot quote).
std::string Printf(const std::string& format) { return "\"$(printf '" + format + "')\""; }

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// A little-endian GeoTIFF in EPSG:28350 whose header claims `width` x `height` float32 cells
// in one-row strips whose offsets lie beyond the file's end: what a damaged or hostile file looks
// like to a reader that trusts it.
void WriteLyingGeoTiff(const std::string& path, uint32_t width, uint32_t height) {
  std::vector<uint8_t> b;
  const auto u16 = [&](uint16_t v) {
    b.push_back(static_cast<uint8_t>(v));
    b.push_back(static_cast<uint8_t>(v >> 8));
  };
  const auto u32 = [&](uint32_t v) {
    u16(static_cast<uint16_t>(v));
    u16(static_cast<uint16_t>(v >> 16));
  };
  const auto f64 = [&](double v) {
    uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    u32(static_cast<uint32_t>(bits));
    u32(static_cast<uint32_t>(bits >> 32));
  };
  constexpr uint16_t kShort = 3, kLong = 4, kDouble = 12;
  constexpr uint32_t kEntries = 13;
  constexpr uint32_t kData = 8 + 2 + kEntries * 12 + 4;  // where the out-of-line values start
  const uint32_t scale_at = kData, tie_at = kData + 24, keys_at = kData + 72,
                 strip_at = kData + 104;
  b.push_back('I');
  b.push_back('I');
  u16(42);
  u32(8);
  u16(kEntries);
  const auto entry = [&](uint16_t tag, uint16_t type, uint32_t count, uint32_t value) {
    u16(tag);
    u16(type);
    u32(count);
    u32(value);
  };
  entry(256, kLong, 1, width);
  entry(257, kLong, 1, height);
  entry(258, kShort, 1, 32);
  entry(259, kShort, 1, 1);
  entry(262, kShort, 1, 1);
  entry(273, kLong, height, strip_at);
  entry(277, kShort, 1, 1);
  entry(278, kLong, 1, 1);
  entry(279, kLong, height, strip_at);
  entry(339, kShort, 1, 3);
  entry(33550, kDouble, 3, scale_at);
  entry(33922, kDouble, 6, tie_at);
  entry(34735, kShort, 16, keys_at);
  u32(0);
  for (double v : {1.0, 1.0, 0.0}) f64(v);
  for (double v : {0.0, 0.0, 0.0, 500000.0, 7500000.0, 0.0}) f64(v);
  for (uint16_t v : {1, 1, 0, 3, 1024, 0, 1, 1, 1025, 0, 1, 1, 3072, 0, 1, 28350}) u16(v);
  f64(0);
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

class HostileCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    static const testing::StoreRecipe recipe{
        "hostile_cli_test", [](const std::string& store, const TempDir&) {
          testing::MakeDemStore(store, "geology/hamersley/dtm_rp.tif", " --name ground");
          RunWrite(store, "tin build " + Quote(store) + " --surface terrain --tolerance 10");
        }};
    testing::CopyRecipeStore(recipe, store_);
    polygon_ = dir_.Path("p.geojson");
    WriteText(polygon_,
              R"({"type":"FeatureCollection","crs":{"type":"name","properties":{"name":)"
              R"("urn:ogc:def:crs:EPSG::28350"}},"features":[{"type":"Feature","properties":)"
              R"({"code":"A"},"geometry":{"type":"Polygon","coordinates":[[[530000,7490000],)"
              R"([540000,7490000],[540000,7500000],[530000,7500000],[530000,7490000]]]}}]})");
  }
  std::string S() const { return Quote(store_); }
  TempDir dir_;
  std::string store_;
  std::string polygon_;
};

// ---- 1. Aborts: no exception escapes main; sizes from headers are checked before allocating.

TEST_F(HostileCliTest, StorePathTooLongIsOneLineNotAnAbort) {
  const CliResult r = RunCli("info " + std::string(5000, 'a'));
  EXPECT_EQ(r.exit_code, 1) << "an abort exits 134: " << r.err;
  ExpectOneLineError(r, "the path is too long");
}

TEST_F(HostileCliTest, StoreInUnreadableDirectoryIsPermissionDenied) {
  const std::string locked = dir_.Path("locked");
  std::filesystem::create_directory(locked);
  std::filesystem::copy_file(store_, locked + "/s.tinbase");
  ::chmod(dir_.dir().c_str(), 0755);
  ::chmod(locked.c_str(), 0);
  const CliResult r = RunCli("info " + Quote(locked + "/s.tinbase"), AsUnprivileged());
  ::chmod(locked.c_str(), 0755);
  ExpectOneLineError(r, "permission denied");
}

TEST_F(HostileCliTest, GeoTiffClaiming2To31SquaredCellsIsRefusedBeforeAllocating) {
  const std::string tif = dir_.Path("huge.tif");
  WriteLyingGeoTiff(tif, 2147483647u, 2147483647u);
  ExpectRejected(store_, "dem import " + S() + " " + Quote(tif),
                 "claims 2147483647 x 2147483647 uncompressed cells");
  // --force lifts the cell limit, not the check of the header against the file. The memory cap
  // keeps a regression from taking the machine down: it would end as "out of memory".
  const CliResult forced =
      RunCli("dem import --force " + S() + " " + Quote(tif), "ulimit -v 4000000;");
  ExpectOneLineError(forced, "truncated or damaged");
}

TEST_F(HostileCliTest, InfoOnAStoreWithoutCrsPrintsNotSet) {
  const std::string bare = StoreTarget(dir_, "bare.tinbase");
  const std::string xyz = dir_.Path("a.xyz");
  WriteText(xyz, "0 0 1\n10 0 2\n0 10 3\n10 10 4\n5 5 5\n");
  RunWrite(bare, "init " + Quote(bare));
  RunWrite(bare, "points import " + Quote(bare) + " " + Quote(xyz) + " --surface p");
  const nlohmann::json j = Json(RunCli("info --json " + Quote(bare)));
  EXPECT_TRUE(j["crs"].is_null());
  const CliResult text = RunCli("info " + Quote(bare));
  EXPECT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("CRS not set"), std::string::npos) << text.out;
}

// ---- 2. A hang: a cell-count limit, with --force to go past it.

TEST_F(HostileCliTest, VrtOfAMillionSquaredCellsHitsTheCellLimit) {
  const std::string vrt = dir_.Path("huge.vrt");
  WriteText(vrt,
            "<VRTDataset rasterXSize=\"1000000\" rasterYSize=\"1000000\"><SRS>EPSG:28350</SRS>"
            "<GeoTransform>500000, 1, 0, 7000000, 0, -1</GeoTransform>"
            "<VRTRasterBand dataType=\"Float32\" band=\"1\"/></VRTDataset>");
  ExpectRejected(store_, "dem import " + S() + " " + Quote(vrt), "--force");
  ExpectRejected(store_, "dem import " + S() + " " + Quote(vrt), "1000000 x 1000000 cells");
}

// ---- 3. Accepted writes that broke invariants.

TEST_F(HostileCliTest, ReimportUnderASurfaceIsRefusedNamingIt) {
  ExpectRejected(store_,
                 "dem import " + S() + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")) +
                     " --name ground",
                 "DEM 'ground' has a surface built on it ('terrain')");
  // A new DEM from the same sheet is fine.
  RunWrite(store_, "dem import " + S() + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")) +
                       " --name ground2");
}

TEST_F(HostileCliTest, ReplaceLevelIsRangeCheckedAgainstTheSurface) {
  const std::string add =
      "polygon add " + S() + " --surface terrain --mode replace " + Quote(polygon_) + " --level ";
  ExpectRejected(store_, add + "1e100", "larger in magnitude than 1e15");
  ExpectRejected(store_, add + "1e12", "is far outside the relief of surface 'terrain'");
  ExpectRejected(store_, add + "-1e7", "is far outside the relief of surface 'terrain'");
  RunWrite(store_, add + "650");
}

TEST_F(HostileCliTest, InfiniteDemCellsAreStoredAsNodataAndSaidSo) {
  Grid grid;
  grid.geometry = GridGeometry{500000, 7500000, 10, -10, 20, 20};
  grid.cells.assign(400, 100.0f);
  grid.cells[0] = std::numeric_limits<float>::infinity();
  grid.cells[21] = -std::numeric_limits<float>::infinity();
  auto crs = Crs::FromUserInput("EPSG:28350");
  ASSERT_TRUE(crs.ok());
  grid.crs_wkt = crs->Wkt();
  const std::string tif = dir_.Path("inf.tif");
  ASSERT_TRUE(WriteGeoTiff(grid, tif).ok());
  const CliResult r = RunWrite(store_, "dem import " + S() + " " + Quote(tif) + " --name inf");
  EXPECT_NE(r.out.find("2 cell(s) of +/-Inf in the sources stored as nodata"), std::string::npos)
      << r.out;
  const CliResult sample = RunCli("dem sample " + S() + " --dem inf --nearest -- 500005 7499995");
  EXPECT_NE(sample.err.find("no data at (500005, 7499995)"), std::string::npos) << sample.err;
  RunWrite(store_, "tin build " + S() + " --dem inf --surface inf --tolerance 1");
}

TEST_F(HostileCliTest, NamesThatAreNotPrintableUtf8AreRefusedAtTheEdge) {
  const std::string xyz = dir_.Path("a.xyz");
  WriteText(xyz, "500000 7500000 1\n500010 7500000 2\n500000 7500010 3\n500010 7500010 4\n");
  const std::string import = "points import " + S() + " " + Quote(xyz) + " --surface ";
  ExpectRejected(store_, import + Printf("a\\nb"), "has a control character at byte 2");
  ExpectRejected(store_, import + Printf("bad\\377"), "is not valid UTF-8 at byte 4");
  ExpectRejected(store_, import + Printf("\\033[31mred"), "has a control character at byte 1");
  ExpectRejected(store_, import + "' padded'", "starts or ends with a space");
  ExpectRejected(store_,
                 "dem import " + S() + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")) +
                     " --name " + Printf("x\\ty"),
                 "DEM name 'x\\x09y' has a control character");
  RunWrite(store_, import + "'Gelände Süd'");
  const nlohmann::json j = Json(RunCli("info --json " + S()));
  EXPECT_EQ(j["surfaces"].size(), 2u);
}

// ---- 5. Misleading messages: say what is really wrong.

TEST_F(HostileCliTest, DirectoryGivenAsStoreSaysSo) {
  ExpectOneLineError(RunCli("info " + Quote(dir_.dir())), "is a directory, not a store");
}

TEST_F(HostileCliTest, ReadOnlyStoreAndReadOnlyDirectorySayPermission) {
  const std::string shelf = dir_.Path("shelf");
  std::filesystem::create_directory(shelf);
  const std::string copy = shelf + "/s.tinbase";
  std::filesystem::copy_file(store_, copy);
  ::chmod(dir_.dir().c_str(), 0755);
  ::chmod(copy.c_str(), 0444);
  ExpectOneLineError(RunCli("polygon remove " + Quote(copy) + " 1", AsUnprivileged()),
                     "permission denied: the store is not writable");
  ::chmod(copy.c_str(), 0666);
  ::chmod(shelf.c_str(), 0555);
  ExpectOneLineError(RunCli("polygon remove " + Quote(copy) + " 1", AsUnprivileged()),
                     "is not writable, and a write needs to create");
  ExpectOneLineError(RunCli("info " + Quote(copy), AsUnprivileged()),
                     "is not writable, and even a reader needs to create");
  ::chmod(shelf.c_str(), 0755);
}

TEST_F(HostileCliTest, TruncatedGeoTiffIsReportedAsTruncated) {
  const std::string plain = dir_.Path("plain.tif");
  ASSERT_EQ(std::system(("gdal_translate -q -co TILED=NO " + Quote(DataPath("dem/elev.tif")) + " " +
                         Quote(plain))
                            .c_str()),
            0)
      << "gdal_translate (Debian gdal-bin) is needed";
  const std::string cut = dir_.Path("cut.tif");
  std::ifstream in(plain, std::ios::binary);
  std::string head(400, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  WriteText(cut, head);
  ExpectRejected(store_, "dem import " + S() + " " + Quote(cut), "truncated or damaged");
}

TEST_F(HostileCliTest, BadWhereIsOneLineWithThePlace) {
  ExpectRejected(store_,
                 "polygon add " + S() + " --surface terrain --mode erase " + Quote(polygon_) +
                     " --where \"code = = 'A\"",
                 "at character 8");
}

TEST_F(HostileCliTest, BrokenUserVersionIsReportedAsDamageNotAsMigrationSql) {
  for (const int version : {3, -5}) {
    SCOPED_TRACE(version);
    {
      auto db = Connection::Open(store_, Connection::Mode::kReadWrite);
      ASSERT_TRUE(db.ok()) << db.status().ToString();
      ASSERT_TRUE((*db)->Exec("PRAGMA user_version = " + std::to_string(version)).ok());
    }
    ExpectRejected(store_, "polygon remove " + S() + " 1",
                   "damaged schema version " + std::to_string(version));
    const CliResult r = RunCli("polygon remove " + S() + " 1");
    EXPECT_EQ(r.err.find("CREATE"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("migration"), std::string::npos) << r.err;
  }
}

// ---- 6. Wrong answers accepted: non-finite or absurd numbers are refused at the edge.

TEST_F(HostileCliTest, NonFiniteAndAbsurdNumbersAreRefusedAtTheEdge) {
  for (const char* bad : {"nan", "inf", "-inf", "1e400"}) {
    SCOPED_TRACE(bad);
    ExpectRejected(store_, "locate " + S() + " --surface terrain -- " + bad + " 7490000",
                   std::string("'") + bad + "' is not finite");
  }
  ExpectRejected(store_, "locate " + S() + " --surface terrain -- 530000 4e300",
                 "'4e300' is larger in magnitude than 1e15");
  ExpectRejected(store_, "tin build " + S() + " --surface t2 --tolerance nan", "is not finite");
  ExpectRejected(store_, "dem sample " + S() + " -- inf 0", "is not finite");
}

TEST_F(HostileCliTest, NegativeMaxCellAreaIsRefused) {
  const std::string xyz = dir_.Path("a.xyz");
  WriteText(xyz, "500000 7500000 1\n500010 7500000 2\n500000 7500010 3\n500010 7500010 4\n");
  ExpectRejected(
      store_, "points import " + S() + " " + Quote(xyz) + " --surface p --thin --max-cell-area=-1",
      "--max-cell-area");
}

TEST_F(HostileCliTest, XyzCoordinatesBeyond1e15AreRefusedNamingTheLine) {
  const std::string xyz = dir_.Path("big.xyz");
  WriteText(xyz, "500000 7500000 1\n500010 7500000 2\n4e300 7500010 3\n500010 7500010 4\n");
  ExpectRejected(store_, "points import " + S() + " " + Quote(xyz) + " --surface p",
                 "big.xyz, line 3: x '4e300' is larger in magnitude than 1e15");
}

// ---- 7. Partial outputs: a failed export leaves no file, not even a temporary one.

TEST_F(HostileCliTest, FailedExportLeavesNoFile) {
  const std::string out = dir_.Path("out.obj");
  ExpectRejected(
      store_, "export " + S() + " --surface terrain --format obj --bbox 0,0,1,1 -o " + Quote(out),
      "");
  for (const auto& entry : std::filesystem::directory_iterator(dir_.dir()))
    EXPECT_EQ(entry.path().filename().string().find("out.obj"), std::string::npos) << entry.path();
}

}  // namespace
}  // namespace tinbase
