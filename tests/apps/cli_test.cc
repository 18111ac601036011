// The tinbase command line end to end on real data: every command of the walking skeleton, its
// --json output, `check` after every write, and bad input rejected with one clear line on stderr,
// a non-zero exit and the store left exactly as it was.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "db/sql/connection.h"
#include "tests/support/cli_support.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::CliResult;
using testing::CopyStore;
using testing::DataPath;
using testing::ExpectRejected;
using testing::Json;
using testing::Quote;
using testing::RunCli;
using testing::RunWrite;
using testing::StoreTarget;
using testing::TableChecksums;
using testing::TempDir;

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    RunWrite(store_, "init " + Quote(store_));
    RunWrite(store_,
             "dem import " + Quote(store_) + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
    RunWrite(store_, "tin build " + Quote(store_) + " --surface terrain --tolerance 10");
  }
  TempDir dir_;
  std::string store_;
};

// TINBASE_THREADS caps the threads a build uses; the surface is the same whatever the cap. A
// cap that is not a whole number of threads is rejected before anything runs.
TEST_F(CliTest, TinBuildIsTheSameOnAnyNumberOfThreads) {
  std::string want;
  for (const char* threads : {"1", "2", "4"}) {
    SCOPED_TRACE(std::string("TINBASE_THREADS=") + threads);
    const std::string surface = std::string("t") + threads;
    const CliResult built =
        RunCli("tin build " + Quote(store_) + " --surface " + surface + " --tolerance 2",
               std::string("TINBASE_THREADS=") + threads);
    ASSERT_EQ(built.exit_code, 0) << built.err;
    const std::string obj = dir_.Path(surface + ".obj");
    ASSERT_EQ(RunCli("export " + Quote(store_) + " --surface " + surface + " --format obj -o " +
                     Quote(obj))
                  .exit_code,
              0);
    std::ifstream in(obj);
    std::stringstream text;
    text << in.rdbuf();
    ASSERT_FALSE(text.str().empty());
    if (want.empty()) want = text.str();
    EXPECT_EQ(text.str(), want);
  }
  for (const char* bad : {"0", "-1", "two", "2x"}) {
    const CliResult r = RunCli("info " + Quote(store_), std::string("TINBASE_THREADS=") + bad);
    EXPECT_NE(r.exit_code, 0) << bad;
    EXPECT_NE(r.err.find("TINBASE_THREADS"), std::string::npos) << bad << ": " << r.err;
  }
}

TEST_F(CliTest, InfoListsTheDemAndTheSurface) {
  auto j = Json(RunCli("info --json " + Quote(store_)));
  ASSERT_EQ(j["dems"].size(), 1u);
  EXPECT_EQ(j["dems"][0]["name"], "dtm_rp");
  EXPECT_EQ(j["dems"][0]["width"], 197);
  EXPECT_EQ(j["dems"][0]["height"], 204);
  EXPECT_EQ(j["crs"], "EPSG:28350");
  ASSERT_EQ(j["surfaces"].size(), 1u);
  EXPECT_EQ(j["surfaces"][0]["name"], "terrain");
  EXPECT_GT(j["surfaces"][0]["triangles"].get<int>(), 100);
  CliResult text = RunCli("info " + Quote(store_));
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.out.find("terrain"), std::string::npos);
}

TEST_F(CliTest, LocateAgreesWithTheDemWithinTheTolerance) {
  auto info = Json(RunCli("info --json " + Quote(store_)));
  const auto& bbox = info["dems"][0]["bbox"];
  for (int i = 1; i < 10; ++i) {
    const double x =
        bbox[0].get<double>() + (bbox[2].get<double>() - bbox[0].get<double>()) * i / 10.3;
    const double y =
        bbox[1].get<double>() + (bbox[3].get<double>() - bbox[1].get<double>()) * i / 10.7;
    const std::string xy = " -- " + std::to_string(x) + " " + std::to_string(y);
    auto where = Json(RunCli("locate --json " + Quote(store_) + " --surface terrain" + xy));
    auto dem = Json(RunCli("dem sample --json " + Quote(store_) + xy));
    // The TIN is within 10 m of every DEM cell; between cells the DEM's bilinear surface can
    // differ from the TIN's plane by a little more than that.
    EXPECT_NEAR(where["z"].get<double>(), dem["z"].get<double>(), 25.0) << xy;
    auto nb = Json(RunCli("neighbours --json " + Quote(store_) + " --surface terrain " +
                          std::to_string(where["triangle"].get<int64_t>())));
    EXPECT_EQ(nb["triangle"], where["triangle"]);
    EXPECT_EQ(nb["vertices"].size(), 3u);
    // Each named neighbour names this triangle back.
    for (const auto& n : nb["neighbours"]) {
      if (n.is_null()) continue;
      auto back = Json(RunCli("neighbours --json " + Quote(store_) + " --surface terrain " +
                              std::to_string(n.get<int64_t>())));
      EXPECT_NE(std::find(back["neighbours"].begin(), back["neighbours"].end(), where["triangle"]),
                back["neighbours"].end());
    }
  }
}

TEST_F(CliTest, ExportsObjAndGeoJson) {
  const std::string obj = dir_.Path("t.obj");
  const std::string geojson = dir_.Path("t.geojson");
  auto info = Json(RunCli("info --json " + Quote(store_)));
  const int triangles = info["surfaces"][0]["triangles"];
  ASSERT_EQ(RunCli("export " + Quote(store_) + " --surface terrain --format obj -o " + Quote(obj))
                .exit_code,
            0);
  std::ifstream in(obj);
  std::string line;
  int faces = 0;
  while (std::getline(in, line)) faces += line.rfind("f ", 0) == 0;
  EXPECT_EQ(faces, triangles);
  ASSERT_EQ(
      RunCli("export " + Quote(store_) + " --surface terrain --format geojson -o " + Quote(geojson))
          .exit_code,
      0);
  std::ifstream gj(geojson);
  auto doc = nlohmann::json::parse(gj);
  EXPECT_EQ(doc["features"].size(), static_cast<size_t>(triangles));
}

TEST_F(CliTest, PolygonsAreDrapedAndTagTheTriangles) {
  const std::string geology = DataPath("geology/hamersley/geology.geojson");
  RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(geology) +
                       " --surface terrain --mode fill --tag-field unitname");
  auto info = Json(RunCli("info --json " + Quote(store_)));
  EXPECT_EQ(info["surfaces"][0]["features"], 61);
  // Neighbouring units share their boundary: each shared edge is one constrained edge.
  EXPECT_GT(info["surfaces"][0]["constraints"].get<int>(), 3000);
  // The centre of the map lies in some unit: the triangle there carries its name.
  const auto& bbox = info["dems"][0]["bbox"];
  const double x = (bbox[0].get<double>() + bbox[2].get<double>()) / 2;
  const double y = (bbox[1].get<double>() + bbox[3].get<double>()) / 2;
  auto where = Json(RunCli("locate --json " + Quote(store_) + " --surface terrain -- " +
                           std::to_string(x) + " " + std::to_string(y)));
  EXPECT_TRUE(where["tag"].is_string()) << where.dump();

  // An erase polygon hides what it covers.
  const std::string square = dir_.Path("square.geojson");
  std::ofstream(square) << R"({"type":"FeatureCollection","crs":{"type":"name","properties":)"
                        << R"({"name":"EPSG:28350"}},"features":[{"type":"Feature","properties":)"
                        << R"({},"geometry":{"type":"Polygon","coordinates":[[)"
                        << "[" << x - 2000 << "," << y - 2000 << "],[" << x + 2000 << ","
                        << y - 2000 << "],[" << x + 2000 << "," << y + 2000 << "],[" << x - 2000
                        << "," << y + 2000 << "],[" << x - 2000 << "," << y - 2000 << "]]]}}]}";
  RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(square) +
                       " --surface terrain --mode erase");
  where = Json(RunCli("locate --json " + Quote(store_) + " --surface terrain -- " +
                      std::to_string(x) + " " + std::to_string(y)));
  EXPECT_FALSE(where["visible"].get<bool>());
  auto changes = Json(RunCli("changes --json --since 1 " + Quote(store_)));
  ASSERT_EQ(changes.size(), 2u);
  EXPECT_EQ(changes[1]["action"], "polygon add");
}

TEST_F(CliTest, BadPolygonsAreRejectedAndChangeNothing) {
  const auto write = [&](const std::string& name, const std::string& coordinates) {
    const std::string path = dir_.Path(name);
    std::ofstream(path) << R"({"type":"FeatureCollection","crs":{"type":"name","properties":)"
                        << R"({"name":"EPSG:28350"}},"features":[{"type":"Feature","properties":)"
                        << R"({},"geometry":{"type":"Polygon","coordinates":)" << coordinates
                        << "}}]}";
    return Quote(path);
  };
  const std::string s = Quote(store_);
  // A bow tie: the ring crosses itself.
  ExpectRejected(store_,
                 "polygon add " + s + " --surface terrain --mode fill " +
                     write("bowtie.geojson",
                           "[[[540000,7497000],[542000,7499000],"
                           "[542000,7497000],[540000,7499000],"
                           "[540000,7497000]]]"),
                 "crosses itself");
  // Far outside the DEM.
  ExpectRejected(store_,
                 "polygon add " + s + " --surface terrain --mode fill " +
                     write("far.geojson", "[[[0,0],[10,0],[10,10],[0,10],[0,0]]]"),
                 "lies wholly outside the data area of surface 'terrain'");
  ExpectRejected(store_,
                 "polygon add " + s + " --surface terrain --mode paint " +
                     write("ok.geojson",
                           "[[[540000,7497000],[541000,7497000],"
                           "[541000,7498000],[540000,7497000]]]"),
                 "paint");
  ExpectRejected(store_,
                 "polygon add " + s + " --surface terrain --mode replace " +
                     write("ok2.geojson",
                           "[[[540000,7497000],[541000,7497000],"
                           "[541000,7498000],[540000,7497000]]]"),
                 "--level");
}

TEST_F(CliTest, ChangesLogHasTheBuild) {
  auto j = Json(RunCli("changes --json " + Quote(store_)));
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0]["action"], "build");
  EXPECT_GT(j[0]["added"].get<int>(), 0);
}

TEST_F(CliTest, PolygonAddRemoveUpdateAndFeatureExport) {
  const std::string geology = Quote(DataPath("geology/hamersley/geology.geojson"));
  RunWrite(store_, "polygon add " + Quote(store_) + " " + geology +
                       " --surface terrain --mode fill --tag-field unitname");
  auto added = Json(RunCli("changes --json " + Quote(store_) + " --since 1"));
  ASSERT_EQ(added.size(), 1u);
  EXPECT_EQ(added[0]["action"], "polygon add");
  EXPECT_GT(added[0]["removed"].get<int64_t>(), 0);
  EXPECT_GT(added[0]["added"].get<int64_t>(), 0);
  RunWrite(store_, "polygon remove " + Quote(store_) + " 3");
  const std::string square = dir_.Path("square.geojson");
  std::ofstream(square)
      << R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": )"
      << R"("urn:ogc:def:crs:EPSG::28350"}}, "features": [{"type": "Feature", "properties": {}, )"
      << R"("geometry": {"type": "Polygon", "coordinates": [[[538000, 7496000], [541000, )"
      << R"(7496000], [541000, 7499000], [538000, 7499000], [538000, 7496000]]]}}]})";
  RunWrite(store_, "polygon update " + Quote(store_) + " 4 " + Quote(square));
  auto edits = Json(RunCli("changes --json " + Quote(store_) + " --since 2"));
  ASSERT_EQ(edits.size(), 2u);
  EXPECT_EQ(edits[0]["action"], "polygon remove");
  EXPECT_EQ(edits[1]["action"], "polygon update");
  const std::string obj = dir_.Path("f.obj");
  RunWrite(store_, "export " + Quote(store_) + " --feature 62 -o " + Quote(obj));
  std::ifstream in(obj);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_GT(std::count(text.begin(), text.end(), 'f'), 10);
  ExpectRejected(store_, "polygon remove " + Quote(store_) + " 999", "no feature 999");
  ExpectRejected(
      store_,
      "polygon add " + Quote(store_) + " " + Quote(square) + " --surface terrain --mode paint",
      "unknown feature mode 'paint' (expected clip, erase, fill, replace, breakline, softline or "
      "points)");
}

TEST_F(CliTest, BadInputIsRejectedAndChangesNothing) {
  const std::string s = Quote(store_);
  ExpectRejected(store_, "dem import " + s + " " + Quote(dir_.Path("missing.tif")), "missing.tif");
  const std::string text = dir_.Path("notes.tif");
  std::ofstream(text) << "this is not a raster\n";
  ExpectRejected(store_, "dem import " + s + " " + Quote(text), "notes.tif");
  ExpectRejected(store_, "dem sample " + s + " -- 0 0", "outside");
  ExpectRejected(store_, "locate " + s + " --surface nosuch -- 0 0", "nosuch");
  ExpectRejected(store_, "locate " + s + " --surface terrain -- 0 0", "outside");
  ExpectRejected(store_, "neighbours " + s + " --surface terrain 99999999", "99999999");
  ExpectRejected(store_, "tin build " + s + " --surface terrain --tolerance 5", "terrain");
  ExpectRejected(store_, "tin build " + s + " --surface t2 --tolerance 0", "tolerance");
  ExpectRejected(store_,
                 "export " + s + " --surface terrain --format dxf -o " + Quote(dir_.Path("x.dxf")),
                 "unknown export format 'dxf'");
  const std::string other = dir_.Path("other.db");
  std::ofstream(other) << "SQLite format 3 but not really\n";
  CliResult r = RunCli("info " + Quote(other));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("not a tinbase store"), std::string::npos) << r.err;
}

// `check` names the first broken triangle and exits non-zero; each corruption is made with SQL.
TEST_F(CliTest, CheckNamesTheFirstBrokenTriangle) {
  const struct {
    const char* sql;
    const char* code;
  } cases[] = {
      {"UPDATE triangles SET v1 = v2, v2 = v1 WHERE id = (SELECT min(id) + 7 FROM triangles)",
       "clockwise-triangle"},
      {"UPDATE triangles SET n0 = NULL WHERE id = (SELECT min(id) + 7 FROM triangles WHERE "
       "n0 IS NOT NULL)",
       "neighbour"},
      // An interior triangle: its three neighbours are left pointing at a missing row. Taken
      // from the middle of the id order (triangles are numbered by block): one of the first
      // ones, in the grid's corner block, may have a vertex on the hull, and its hole then
      // joins the outer boundary, so the Euler check is the first problem named.
      {"DELETE FROM triangles WHERE id = (SELECT id FROM triangles WHERE n0 IS NOT NULL AND n1 IS "
       "NOT NULL AND n2 IS NOT NULL ORDER BY id LIMIT 1 OFFSET (SELECT count(*) / 2 FROM "
       "triangles))",
       ""},
      {"UPDATE triangles SET block = block + 1 WHERE id = (SELECT min(id) + 7 FROM triangles)",
       "wrong-block"},
  };
  int index = 0;
  for (const auto& c : cases) {
    const std::string copy = StoreTarget(dir_, "corrupt" + std::to_string(index++) + ".tinbase");
    ASSERT_EQ(RunCli("check " + Quote(store_)).exit_code, 0);
    CopyStore(store_, copy);
    {
      auto db = Connection::Open(copy, Connection::Mode::kReadWrite);
      ASSERT_TRUE(db.ok());
      ASSERT_TRUE((*db)->Exec(c.sql).ok()) << c.sql;
    }
    CliResult r = RunCli("check " + Quote(copy));
    EXPECT_NE(r.exit_code, 0) << c.sql;
    EXPECT_NE(r.err.find("triangle"), std::string::npos) << c.sql << "\n" << r.err;
    // The corrupted triangle's own problem is among those listed (a neighbour with a lower id
    // may be named first, for the link it no longer matches).
    auto j = nlohmann::json::parse(RunCli("check --json " + Quote(copy)).out);
    EXPECT_FALSE(j["ok"].get<bool>());
    EXPECT_FALSE(j["problems"].empty());
    EXPECT_NE(j["problems"].dump().find(c.code), std::string::npos) << c.sql << "\n" << j.dump();
  }
}

TEST(CliStandalone, RasterWithoutCrsIsRejected) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "s.tinbase");
  ASSERT_EQ(RunCli("init " + Quote(store)).exit_code, 0);
  // An ASCII grid has a geotransform but no CRS.
  const std::string asc = dir.Path("nocrs.asc");
  std::ofstream(asc) << "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 10\n"
                        "1 2 3\n4 5 6\n7 8 9\n";
  ExpectRejected(store, "dem import " + Quote(store) + " " + Quote(asc), "CRS");
}

// Regression: `info --json` on a store whose CRS was never set built a std::string from null and
// aborted.
TEST(CliStandalone, InfoOfAStoreWithNoCrsSaysNull) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "s.tinbase");
  ASSERT_EQ(RunCli("init " + Quote(store)).exit_code, 0);
  CliResult r = RunCli("info --json " + Quote(store));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Json(r)["crs"].is_null());
  EXPECT_EQ(RunCli("info " + Quote(store)).exit_code, 0);
}

TEST(CliStandalone, InitWithCrsAndRefusalToOverwrite) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "s.tinbase");
  ASSERT_EQ(RunCli("init " + Quote(store) + " --crs EPSG:32632").exit_code, 0);
  auto j = Json(RunCli("info --json " + Quote(store)));
  EXPECT_EQ(j["crs"], "EPSG:32632");
  CliResult again = RunCli("init " + Quote(store));
  EXPECT_NE(again.exit_code, 0);
  EXPECT_NE(again.err.find("already exists"), std::string::npos);
}

TEST(CliStandalone, SrtmTileIsWarpedToUtmAndBuilt) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "s.tinbase");
  RunWrite(store, "init " + Quote(store));
  RunWrite(store, "dem import " + Quote(store) + " " + Quote(DataPath("dem/N43E007.hgt")));
  auto j = Json(RunCli("info --json " + Quote(store)));
  EXPECT_EQ(j["crs"], "EPSG:32632");  // 7.5E, 43.5N is in UTM zone 32N
  RunWrite(store, "tin build " + Quote(store) + " --surface alps --tolerance 20");
}

}  // namespace
}  // namespace tinbase
