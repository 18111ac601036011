// Issue 29, tried again (session 18): new hostile but fair inputs to the command line, table
// driven. Each case must end in one line "tinbase: <what is wrong, where>", a non-zero exit and
// the store unchanged (ExpectRejected compares a checksum of every table), or, where the input is
// usable after all, in a store that `check --full` passes. The cases are listed, by class, in
// docs/reliability.md ("Tried again").
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "tests/support/cli_support.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::CliResult;
using testing::DataPath;
using testing::ExpectRejected;
using testing::Quote;
using testing::RunCli;
using testing::RunWrite;
using testing::TempDir;

struct Case {
  std::string args;      // after the command's store, or the whole command line (see the test)
  std::string expected;  // in the one line of stderr
};

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// A command that must fail with one line naming `expected`, when there is no store to compare.
void ExpectOneLineError(const CliResult& r, const std::string& expected) {
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find(expected), std::string::npos) << "stderr: " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line expected: " << r.err;
  EXPECT_EQ(r.err.rfind("tinbase: ", 0), 0u) << r.err;
}

// A GeoJSON FeatureCollection in EPSG:28350 (unless `crs` names another) of one feature whose
// properties are `properties` and whose geometry is `geometry` (JSON text).
std::string Collection(const std::string& geometry, const std::string& properties = "{}",
                       const std::string& crs = "EPSG::28350") {
  return R"({"type":"FeatureCollection","crs":{"type":"name","properties":{"name":"urn:ogc:def:crs:)" +
         crs + R"("}},"features":[{"type":"Feature","properties":)" + properties +
         R"(,"geometry":)" + geometry + "}]}";
}

// A square of side 1000 at the middle of the Hamersley DEM, as a GeoJSON polygon.
const char* kSquare =
    R"({"type":"Polygon","coordinates":[[[539000,7497000],[540000,7497000],[540000,7498000],)"
    R"([539000,7498000],[539000,7497000]]]})";

class HostileInputsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    base_dir_ = new TempDir();
    const std::string base = base_dir_->Path("base.tinbase");
    RunWrite(base, "init " + Quote(base) + " --crs EPSG:28350");
    RunWrite(base,
             "dem import " + Quote(base) + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
    RunWrite(base, "tin build " + Quote(base) + " --surface terrain --tolerance 20");
  }
  static void TearDownTestSuite() {
    delete base_dir_;
    base_dir_ = nullptr;
  }
  void SetUp() override {
    store_ = dir_.Path("s.tinbase");
    std::filesystem::copy_file(base_dir_->Path("base.tinbase"), store_);
  }
  std::string S() const { return Quote(store_); }
  std::string File(const std::string& name, const std::string& text) const {
    WriteText(dir_.Path(name), text);
    return Quote(dir_.Path(name));
  }
  // Runs each case as "<command> STORE <args>" and demands its rejection.
  void ExpectAllRejected(const std::string& command, const std::vector<Case>& cases) {
    for (const Case& c : cases) {
      SCOPED_TRACE(command + " " + c.args);
      ExpectRejected(store_, command + " " + S() + " " + c.args, c.expected);
    }
  }

  static TempDir* base_dir_;
  TempDir dir_;
  std::string store_;
};

TempDir* HostileInputsTest::base_dir_ = nullptr;

// ---- Store paths: every odd thing a path can name.

TEST_F(HostileInputsTest, OddStorePathsSayWhatTheyAre) {
  const std::string fifo = dir_.Path("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  std::filesystem::create_symlink(dir_.Path("loop2"), dir_.Path("loop1"));
  std::filesystem::create_symlink(dir_.Path("loop1"), dir_.Path("loop2"));
  WriteText(dir_.Path("empty.tinbase"), "");
  WriteText(dir_.Path("text.tinbase"), "hello\n");
  WriteText(dir_.Path("zeros.tinbase"), std::string(100000, '\0'));
  const std::vector<Case> cases = {
      {"''", "names no store file"},
      {"/dev/null", "is not a regular file"},
      {"/dev/zero", "is not a regular file"},
      {Quote(fifo), "is not a regular file"},
      {Quote(dir_.Path("loop1")), "too many symbolic links"},
      {Quote(dir_.Path("empty.tinbase")), "is not a tinbase store"},
      {Quote(dir_.Path("text.tinbase")), "is not a tinbase store"},
      {Quote(dir_.Path("zeros.tinbase")), "is not a tinbase store"},
      {S() + "/", "a part of the path is not a directory"},
      {Quote(dir_.Path("missing.tinbase")), "no such store"},
      {Quote(dir_.Path("no/such/dir/s.tinbase")), "no such store"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    ExpectOneLineError(RunCli("info " + c.args), c.expected);
    ExpectOneLineError(RunCli("polygon remove " + c.args + " 1"), c.expected);
  }
}

TEST_F(HostileInputsTest, ATruncatedStoreIsCalledDamagedNotSomethingElse) {
  std::ifstream in(store_, std::ios::binary);
  std::string head(40000, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  const std::string cut = dir_.Path("cut.tinbase");
  WriteText(cut, head);
  for (const std::string command : {"info ", "check --full ", "polygon remove "}) {
    SCOPED_TRACE(command);
    const CliResult r = RunCli(command + Quote(cut) + (command[0] == 'p' ? " 1" : ""));
    ExpectOneLineError(r, "is a damaged database");
    EXPECT_NE(r.err.find(".recover"), std::string::npos) << r.err;
  }
}

TEST_F(HostileInputsTest, InitWhereNoStoreCanBeSays) {
  const std::vector<Case> cases = {
      {Quote(dir_.Path("no/such/dir/s.tinbase")), "there is no directory"},
      {S(), "a file already exists there"},
      {Quote(dir_.dir()), "a file already exists there"},
      {"''", "names no store file"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    ExpectOneLineError(RunCli("init " + c.args + " --crs EPSG:28350"), c.expected);
  }
  EXPECT_FALSE(std::filesystem::exists(dir_.Path("no")));
}

// ---- Odd coordinate reference systems.

TEST_F(HostileInputsTest, StoreCrsMustHaveAPlaneOrTheEarthsSurface) {
  const std::vector<Case> cases = {
      {"EPSG:999999", "unknown coordinate reference system 'EPSG:999999'"},
      {"garbage", "unknown coordinate reference system 'garbage'"},
      {"EPSG:4978", "is a geocentric CRS"},
      {"EPSG:5773", "is a vertical CRS alone"},
      {"EPSG:5711", "is a vertical CRS alone"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const std::string path = dir_.Path("crs.tinbase");
    ExpectOneLineError(RunCli("init " + Quote(path) + " --crs " + Quote(c.args)), c.expected);
    EXPECT_FALSE(std::filesystem::exists(path)) << "a refused init left a file";
  }
  // Usable ones, each a store the DEM can be warped onto and checked.
  for (const char* crs : {"EPSG:4326", "+proj=utm +zone=50 +south", "EPSG:28350+5711"}) {
    SCOPED_TRACE(crs);
    const std::string path = dir_.Path("ok.tinbase");
    std::filesystem::remove(path);
    RunWrite(path, "init " + Quote(path) + " --crs " + Quote(crs));
    RunWrite(path,
             "dem import " + Quote(path) + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
    RunWrite(path, "tin build " + Quote(path) + " --surface t --tolerance 20");
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
  }
}

TEST_F(HostileInputsTest, FeaturesInCrsesTheyCannotBeIn) {
  ExpectAllRejected(
      "polygon add",
      {{File("ll.geojson", Collection(kSquare, "{}", "EPSG::4326")) +
            " --surface terrain --mode fill",
        "cannot be reprojected from EPSG:4326"},
       {File("far.geojson", Collection(R"({"type":"Polygon","coordinates":[[[7,-90],[8,-90],)"
                                       R"([8,-89.9],[7,-89.9],[7,-90]]]})",
                                       "{}", "OGC:1.3:CRS84")) +
            " --surface terrain --mode fill",
        "lies wholly outside the data area"}});
}

// ---- Numbers on the command line: only decimal numbers, in range, whole where whole.

TEST_F(HostileInputsTest, NumbersMustBeDecimalAndInRange) {
  ExpectAllRejected("tin build",
                    {
                        {"--surface t2 --tolerance ''", "'' is not a number"},
                        {"--surface t2 --tolerance 0x10", "'0x10' is not a number"},
                        {"--surface t2 --tolerance 0x1p5", "'0x1p5' is not a number"},
                        {"--surface t2 --tolerance ' 30'", "' 30' is not a number"},
                        {"--surface t2 --tolerance '30 '", "'30 ' is not a number"},
                        {"--surface t2 --tolerance 10abc", "'10abc' is not a number"},
                        {"--surface t2 --tolerance 1e999", "is not finite"},
                        {"--surface t2 --tolerance 0", "tolerance must be a positive number"},
                        {"--surface t2 --tolerance -1", "tolerance must be a positive number"},
                    });
  ExpectAllRejected("polygon remove", {
                                          {"99999999999999999999", "is out of range"},
                                          {"-- -99999999999999999999", "is out of range"},
                                          {"0x10", "'0x10' is not a whole number"},
                                          {"1.5", "'1.5' is not a whole number"},
                                          {"1e3", "'1e3' is not a whole number"},
                                          {"''", "'' is not a whole number"},
                                      });
  ExpectAllRejected("revert", {
                                  {"99999999999999999999", "is out of range"},
                                  {"0", "no transaction 0"},
                                  {"-- -1", "no transaction -1"},
                                  {"1", "is not an edit of features"},
                              });
  ExpectAllRejected("tiles build",
                    {
                        {"--surface terrain --max-zoom -1", "--max-zoom -1 is outside 0..24"},
                        {"--surface terrain --max-zoom 25", "--max-zoom 25 is outside 0..24"},
                        {"--surface terrain --max-zoom 99999999999", "--max-zoom = 99999999999"},
                        {"--surface terrain --window-triangles -1", "must be positive"},
                        {"--surface terrain --window-triangles 0", "must be positive"},
                    });
  ExpectAllRejected("changes", {{"--since 1e3", "'1e3' is not a whole number"}});
  for (const Case& c : std::vector<Case>{
           {"measure volume " + S() + " --surface terrain --level 1e16",
            "'1e16' is larger in magnitude than 1e15"},
           {"measure volume " + S() + " --surface terrain --level 0x10", "is not a number"},
           {"contours " + S() + " --surface terrain --interval 1e-9 -o " +
                Quote(dir_.Path("c.gpkg")),
            "(at most 100000)"},
           {"contours " + S() + " --surface terrain --interval 5 --base 1e20 -o " +
                Quote(dir_.Path("c.gpkg")),
            "'1e20' is larger in magnitude than 1e15"},
           {"locate " + S() + " --surface terrain -- 0x1p19 7497340", "is not a number"},
       }) {
    SCOPED_TRACE(c.args);
    ExpectRejected(store_, c.args, c.expected);
  }
}

// ---- Vector files: encodings, empty, cut short, absurd.

TEST_F(HostileInputsTest, BadPolygonFilesAreRefusedNamingThePlace) {
  const std::string add = " --surface terrain --mode fill";
  const std::string deep = R"({"type":"FeatureCollection","features":[{"type":"Feature",)"
                           R"("properties":{},"geometry":{"type":"Polygon","coordinates":)" +
                           std::string(100000, '[') + std::string(100000, ']') + "}}]}";
  const std::string square = Collection(kSquare);
  std::string utf16;
  for (char c : square) utf16 += std::string{c, '\0'};
  ExpectAllRejected(
      "polygon add",
      {
          {File("empty.geojson", "") + add, "not a vector source GDAL can read"},
          {File("obj.geojson", "{}") + add, "not a vector source GDAL can read"},
          {File("none.geojson", R"({"type":"FeatureCollection","features":[]})") + add,
           "no features"},
          {File("cut.geojson", square.substr(0, 150)) + add, "not a vector source GDAL can read"},
          {File("utf16.geojson", "\xff\xfe" + utf16) + add, "not a vector source GDAL can read"},
          {File("deep.geojson", deep) + add, "not a vector source GDAL can read"},
          {File("point.geojson", Collection(R"({"type":"Point","coordinates":[539000,7497000]})")) +
               add,
           "geometry is a Point"},
          {File("null.geojson", Collection("null")) + add, "feature has no geometry"},
          {File("two.geojson", Collection(R"({"type":"Polygon","coordinates":[[[539000,7497000],)"
                                          R"([540000,7497000],[539000,7497000]]]})")) +
               add,
           "fewer than 3 distinct points"},
          {File("bow.geojson", Collection(R"({"type":"Polygon","coordinates":[[[539000,7497000],)"
                                          R"([540000,7498000],[540000,7497000],[539000,7498000],)"
                                          R"([539000,7497000]]]})")) +
               add,
           "ring crosses itself"},
          {File("big.geojson",
                Collection(R"({"type":"Polygon","coordinates":[[[539000,7497000],)"
                           R"([1e300,7497000],[540000,7498000],[539000,7497000]]]})")) +
               add,
           "feature 0, ring 0, vertex 1: coordinate (1e+300, 7497000) is larger in magnitude"},
          {File("badutf.geojson", Collection(kSquare, "{\"code\":\"\xff\xfe\"}")) + add,
           "feature 0, field 'code': the name or value is not valid UTF-8"},
          {File("badkey.geojson", Collection(kSquare, "{\"\xff\":\"A\"}")) + add,
           "field '\\xFF': the name or value is not valid UTF-8"},
          {Quote(dir_.dir()) + add, "not a vector source GDAL can read"},
          {Quote(dir_.Path("missing.geojson")) + add, "no such file"},
          {File("ok.geojson", square) + " --surface terrain --mode bogus", "bogus"},
          {File("ok2.geojson", square) + " --surface nosuch --mode fill", "no surface named"},
      });
  // A byte-order mark and CRLF line ends are text as any editor writes it: accepted.
  RunWrite(store_, "polygon add " + S() + " " + File("bom.geojson", "\xef\xbb\xbf" + square) + add);
}

// ---- Point files: the XYZ reader and the LAS reader given what they cannot use.

TEST_F(HostileInputsTest, BadPointFilesAreRefusedNamingThePlace) {
  ExpectAllRejected(
      "points add",
      {
          {File("two.xyz", "539300 7497340\n") + " --surface terrain", "line 1: expected x y z"},
          {File("bigz.xyz", "539300 7497340 1e300\n") + " --surface terrain",
           "line 1: z '1e300' is larger in magnitude than 1e15"},
          {File("farz.xyz", "539300 7497340 1e7\n") + " --surface terrain",
           "is far outside the relief"},
          {File("comma.xyz", "539300,5 7497340 500\n") + " --surface terrain",
           "line 1: expected x y z"},
          {File("nul.xyz", std::string("539300") + '\0' + " 7497340 500\n") + " --surface terrain",
           "line 1"},
          {File("empty.xyz", "") + " --surface terrain", "no points"},
          {File("nan.xyz", "nan 7497340 500\n") + " --surface terrain", "is not finite"},
          {File("out.xyz", "0 0 500\n") + " --surface terrain", "lies outside surface"},
          {Quote(DataPath("las/mvk-thin.las")) + " --surface terrain", "lies outside surface"},
          {File("huge.geojson", R"({"type":"FeatureCollection","features":[{"type":"Feature",)"
                                R"("properties":{},"geometry":{"type":"Point","coordinates":)"
                                R"([1e300,7497340,500]}}]})") +
               " --surface terrain",
           "huge.geojson, feature 0: a coordinate is larger in magnitude than 1e15"},
      });
  std::ifstream in(DataPath("las/mvk-thin.las"), std::ios::binary);
  const std::string las((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ExpectAllRejected(
      "points import",
      {
          {File("one.xyz", "1 1 1\n") + " --surface one", "span no triangle"},
          {File("line.xyz", "0 0 1\n1 1 1\n2 2 1\n3 3 1\n") + " --surface line",
           "span no triangle"},
          {File("same.xyz", "5 5 1\n5 5 1\n5 5 1\n") + " --surface same", "span no triangle"},
          {File("header.las", las.substr(0, 227)) + " --surface h", "truncated"},
          {File("h100.las", las.substr(0, 100)) + " --surface h", "truncated"},
          {File("empty.las", "") + " --surface h", ""},
      });
  // CRLF line ends are accepted.
  RunWrite(store_, "points add " + S() + " " +
                       File("crlf.xyz", "539300 7497340 500\r\n539500 7497540 510\r\n") +
                       " --surface terrain");
}

// ---- Rasters that are not what they say.

TEST_F(HostileInputsTest, BadRastersAreRefused) {
  std::string noise(5000, '\0');
  for (size_t i = 0; i < noise.size(); ++i) noise[i] = static_cast<char>((i * 7919) % 251);
  ExpectAllRejected(
      "dem import",
      {
          {File("empty.tif", ""), "not a raster GDAL can read"},
          {File("noise.tif", noise), "not a raster GDAL can read"},
          {Quote(dir_.dir()), "is a directory, not a raster"},
          {Quote(dir_.Path("missing.tif")), "no such file"},
          {File("nosource.vrt",
                "<VRTDataset rasterXSize=\"10\" rasterYSize=\"10\"><SRS>EPSG:28350</SRS>"
                "<GeoTransform>500000, 1, 0, 7000000, 0, -1</GeoTransform><VRTRasterBand "
                "dataType=\"Float32\" band=\"1\"><SimpleSource><SourceFilename>" +
                    dir_.Path("missing.tif") +
                    "</SourceFilename></SimpleSource>"
                    "</VRTRasterBand></VRTDataset>") +
               " --name v",
           ""},
      });
}

// ---- A server that cannot start says why (a timeout guards against one that starts anyway).

TEST_F(HostileInputsTest, ServeWithBadOptionsSaysWhy) {
  WriteText(dir_.Path("empty.token"), "\n");
  const std::vector<Case> cases = {
      {S() + " --listen nonsense", "is not host:port"},
      {S() + " --listen 127.0.0.1:99999", "is not a number from 0 to 65535"},
      {S() + " --listen 127.0.0.1:-1", "is not a number from 0 to 65535"},
      {S() + " --listen 256.0.0.1:0", "cannot listen on 256.0.0.1"},
      {S() + " --token-file " + Quote(dir_.Path("missing")), "cannot be read"},
      {S() + " --token-file " + Quote(dir_.Path("empty.token")), "the first line is empty"},
      {S() + " --max-body-mib 0", "not in range 1 to 1024"},
      {S() + " --max-body-mib 99999999999999999999", "not in range 1 to 1024"},
      {Quote(dir_.Path("missing.tinbase")), "no such store"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const std::string listen =
        c.args.find("--listen") == std::string::npos ? " --listen 127.0.0.1:0" : "";
    ExpectOneLineError(RunCli("serve " + c.args + listen, "timeout 60"), c.expected);
  }
}

// ---- Two commands at once: one wins, the other is refused cleanly, or both land.

// Runs `a` and `b` at the same moment; returns their results.
std::pair<CliResult, CliResult> AtOnce(const std::string& a, const std::string& b) {
  CliResult ra, rb;
  std::thread first([&] { ra = RunCli(a); });
  rb = RunCli(b);
  first.join();
  return {ra, rb};
}

TEST_F(HostileInputsTest, TwoCommandsAtOnce) {
  {
    SCOPED_TRACE("two builds of one surface name");
    const std::string build = "tin build " + S() + " --surface same --tolerance 30";
    auto [a, b] = AtOnce(build, build);
    EXPECT_EQ((a.exit_code == 0) + (b.exit_code == 0), 1) << a.err << b.err;
    ExpectOneLineError(a.exit_code == 0 ? b : a, "already exists");
  }
  {
    SCOPED_TRACE("two inits of one path");
    const std::string init = "init " + Quote(dir_.Path("twice.tinbase")) + " --crs EPSG:28350";
    auto [a, b] = AtOnce(init, init);
    EXPECT_EQ((a.exit_code == 0) + (b.exit_code == 0), 1) << a.err << b.err;
    ExpectOneLineError(a.exit_code == 0 ? b : a, "a file already exists there");
    RunWrite(dir_.Path("twice.tinbase"), "info " + Quote(dir_.Path("twice.tinbase")));
  }
  {
    SCOPED_TRACE("two polygon adds over one place");
    const std::string add = " --surface terrain --mode fill";
    auto [a, b] = AtOnce("polygon add " + S() + " " + File("a.geojson", Collection(kSquare)) + add,
                         "polygon add " + S() + " " + File("b.geojson", Collection(kSquare)) + add);
    EXPECT_EQ(a.exit_code, 0) << a.err;
    EXPECT_EQ(b.exit_code, 0) << b.err;
    RunWrite(store_, "info " + S());
  }
}

// ---- Outputs that cannot be written.

TEST_F(HostileInputsTest, OutputsThatCannotBeWrittenLeaveNothing) {
  const std::string e = "export " + S() + " --surface terrain --format obj -o ";
  for (const Case& c : std::vector<Case>{
           {e + Quote(dir_.Path("no/x.obj")), "no directory"},
           {e + Quote(dir_.dir()), "it is a directory"},
           {e + "''", "no output path given"},
           {"export " + S() + " --surface terrain --format nosuch -o x", "unknown export format"},
           {"export " + S() + " --surface terrain --format obj --bbox 5,5,1,1 -o " +
                Quote(dir_.Path("x.obj")),
            "min is above max"},
       }) {
    SCOPED_TRACE(c.args);
    ExpectRejected(store_, c.args, c.expected);
  }
  EXPECT_FALSE(std::filesystem::exists(dir_.Path("no")));
  EXPECT_FALSE(std::filesystem::exists(dir_.Path("x.obj")));
}

}  // namespace
}  // namespace tinbase
