// `tinbase measure area|volume|cutfill|slope` and `tinbase contours` through the real binary:
// answers on analytic surfaces stored through the API (planes: exact; a paraboloid's contours),
// layers read back by ogrinfo (not ours), a stored feature measured the same as its file, and
// each bad input rejected with one line, no output file and the store unchanged.
#include <gtest/gtest.h>

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/PolygonArea.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <string>

#include "db/store.h"
#include "db/surface_store.h"
#include "tests/core/measure/analytic_tins.h"
#include "tests/support/cli_support.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
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

constexpr double kX = 600000, kY = 5100000;

// Runs a program we did not write (ogrinfo); fails the test when it cannot run.
std::string RunTool(const std::string& command) {
  std::string out;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) {
    ADD_FAILURE() << "cannot run " << command;
    return out;
  }
  char buf[4096];
  size_t n = 0;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
  const int status = pclose(pipe);
  EXPECT_EQ(status, 0) << command << " failed (is GDAL's ogrinfo installed?)\n" << out;
  return out;
}

std::string Ogrinfo(const std::string& path) {
  return RunTool("ogrinfo -ro -al -so " + Quote(path));
}

std::string Square(const TempDir& dir, const std::string& name, double x0, double y0, double x1,
                   double y1, int epsg) {
  return testing::WritePolygons(dir, name, {{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}}}},
                                epsg);
}

class MeasureCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "m.tinbase");
    {
      auto store = Store::Create(store_, "EPSG:32632");
      ASSERT_TRUE(store.ok()) << store.status().ToString();
      // plane: z = 100 + u / 10 for u = x - kX, over [0, 200] x [0, 100];
      // flat: z = 110 over [100, 300] x [0, 100]; far: nowhere near;
      // bowl: z = r^2 / 100 around (kX + 500, kY + 500), over a 100 m square.
      Add(**store, "plane",
          testing::GridTin(8, 4, kX, kY, kX + 200, kY + 100,
                           [](double x, double) { return 100 + (x - kX) / 10; }));
      Add(**store, "flat",
          testing::GridTin(3, 5, kX + 100, kY, kX + 300, kY + 100,
                           [](double, double) { return 110; }));
      Add(**store, "far",
          testing::GridTin(1, 1, kX + 5000, kY, kX + 5100, kY + 100,
                           [](double, double) { return 0; }));
      Add(**store, "bowl",
          testing::GridTin(40, 40, kX + 450, kY + 450, kX + 550, kY + 550, [](double x, double y) {
            return ((x - kX - 500) * (x - kX - 500) + (y - kY - 500) * (y - kY - 500)) / 100;
          }));
    }
    s_ = Quote(store_);
  }

 public:
  static void Add(Store& store, const std::string& name, const Tin& tin) {
    auto tx = store.BeginWrite();
    ASSERT_TRUE(tx.ok());
    SurfaceInfo spec;
    spec.name = name;
    spec.kind = SurfaceKind::kFree;
    spec.method = "test";
    ASSERT_TRUE(SurfaceStore(store).Create(spec, tin).ok());
    ASSERT_TRUE((*tx)->Commit().ok());
  }

 protected:
  TempDir dir_;
  std::string store_;
  std::string s_;
};

TEST_F(MeasureCliTest, AreaOfAPlane) {
  const auto j = Json(RunCli("measure area --json " + s_ + " --surface plane"));
  EXPECT_EQ(j["surface"], "plane");
  EXPECT_EQ(j["crs"], "EPSG:32632");
  EXPECT_EQ(j["plan_area"], "map plane");
  EXPECT_EQ(j["total"]["triangles"], 64);
  EXPECT_NEAR(j["total"]["plan_m2"].get<double>(), 20000, 1e-6);
  EXPECT_NEAR(j["total"]["surface_m2"].get<double>(), 20000 * std::sqrt(1.01), 1e-6);
  ASSERT_EQ(j["tags"].size(), 1u);
  EXPECT_TRUE(j["tags"][0]["tag"].is_null());
  // A window: the triangles meeting [0, 50] x [0, 100] are the first two columns of cells.
  const auto w = Json(RunCli("measure area --json " + s_ + " --surface plane --bbox " +
                             std::to_string(kX) + "," + std::to_string(kY) + "," +
                             std::to_string(kX + 40) + "," + std::to_string(kY + 100)));
  EXPECT_NEAR(w["total"]["plan_m2"].get<double>(), 5000, 1e-6);
  const CliResult text = RunCli("measure area " + s_ + " --surface plane");
  EXPECT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("64 visible triangles, plan area 20000 m2"), std::string::npos)
      << text.out;
}

// z from 100 to 120 against 105: below over u < 50 (12500 m3), above over the rest (112500 m3).
TEST_F(MeasureCliTest, VolumeAgainstALevel) {
  const auto j = Json(RunCli("measure volume --json " + s_ + " --surface plane --level 105"));
  EXPECT_NEAR(j["above_m3"].get<double>(), 112500, 1e-6);
  EXPECT_NEAR(j["below_m3"].get<double>(), 12500, 1e-6);
  EXPECT_NEAR(j["above_area_m2"].get<double>(), 15000, 1e-6);
  EXPECT_NEAR(j["below_area_m2"].get<double>(), 5000, 1e-6);
  EXPECT_NEAR(j["plan_area_m2"].get<double>(), 20000, 1e-6);
  EXPECT_EQ(j["level"], 105);
  // Inside [150, 200] x [0, 100] against 0: the mean z (117.5) over 5000 m2.
  const std::string square = Square(dir_, "sq.geojson", kX + 150, kY, kX + 200, kY + 100, 32632);
  const auto p = Json(RunCli("measure volume --json " + s_ + " --surface plane --level 0 " +
                             "--polygon " + Quote(square)));
  EXPECT_TRUE(p["inside_polygon"].get<bool>());
  EXPECT_NEAR(p["above_m3"].get<double>(), 587500, 1e-6);
}

TEST_F(MeasureCliTest, VolumeRejectsALevelThatIsNotANumber) {
  ExpectRejected(store_, "measure volume " + s_ + " --surface plane --level nan",
                 "--level must be a finite number, got 'nan'");
  ExpectRejected(store_, "measure volume " + s_ + " --surface plane --level inf",
                 "--level must be a finite number");
  ExpectRejected(store_, "measure volume " + s_ + " --surface plane --level 12x",
                 "--level: '12x' is not a number");
  ExpectRejected(store_, "measure volume " + s_ + " --surface nope --level 1",
                 "no surface named 'nope'");
}

// Over the overlap [100, 200] x [0, 100] the flat top (110) lies below the plane (110 to 120):
// all cut, 0.1 * u - 10 integrated, 50000 m3; inside [150, 200] 37500 m3.
TEST_F(MeasureCliTest, CutFillBetweenTwoSurfaces) {
  auto j = Json(RunCli("measure cutfill --json " + s_ + " --base plane --top flat"));
  EXPECT_EQ(j["base"], "plane");
  EXPECT_EQ(j["top"], "flat");
  EXPECT_FALSE(j["inside_polygon"].get<bool>());
  EXPECT_NEAR(j["cut_m3"].get<double>(), 50000, 1e-6);
  EXPECT_NEAR(j["fill_m3"].get<double>(), 0, 1e-6);
  EXPECT_NEAR(j["net_m3"].get<double>(), -50000, 1e-6);
  EXPECT_NEAR(j["plan_area_m2"].get<double>(), 10000, 1e-6);
  const std::string square = Square(dir_, "sq.geojson", kX + 150, kY, kX + 200, kY + 100, 32632);
  j = Json(RunCli("measure cutfill --json " + s_ + " --base plane --top flat --polygon " +
                  Quote(square)));
  EXPECT_TRUE(j["inside_polygon"].get<bool>());
  EXPECT_NEAR(j["cut_m3"].get<double>(), 37500, 1e-6);
  EXPECT_NEAR(j["plan_area_m2"].get<double>(), 5000, 1e-6);
}

TEST_F(MeasureCliTest, CutFillRejectsSurfacesThatDoNotOverlap) {
  ExpectRejected(store_, "measure cutfill " + s_ + " --base plane --top far",
                 "surfaces 'plane' and 'far' do not overlap");
  const std::string away = Square(dir_, "away.geojson", kX + 10, kY + 10, kX + 20, kY + 20, 32632);
  ExpectRejected(store_,
                 "measure cutfill " + s_ + " --base plane --top flat --polygon " + Quote(away),
                 "surfaces 'plane' and 'flat' do not overlap inside the polygon");
  ExpectRejected(store_, "measure cutfill " + s_ + " --base plane --top flat --feature 7",
                 "no feature 7 on surface 'plane' or 'flat'");
}

// Every triangle of z = 100 + x / 10 rises eastwards: slope atan(0.1), facing west (270).
TEST_F(MeasureCliTest, SlopeAsCsvJsonAndALayer) {
  const double slope = std::atan(0.1) * 180 / M_PI;
  CliResult csv = RunCli("measure slope " + s_ + " --surface plane");
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  std::istringstream lines(csv.out);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "triangle,slope_deg,aspect_deg,tag");
  int rows = 0;
  while (std::getline(lines, line)) {
    ++rows;
    double id = 0, s = 0, a = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,", &id, &s, &a), 3) << line;
    EXPECT_NEAR(s, slope, 1e-9);
    EXPECT_NEAR(a, 270, 1e-9);
  }
  EXPECT_EQ(rows, 64);
  CliResult json = RunCli("measure slope --json " + s_ + " --surface plane");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  std::istringstream jl(json.out);
  std::getline(jl, line);
  const auto first = nlohmann::json::parse(line);
  EXPECT_NEAR(first["slope_deg"].get<double>(), slope, 1e-9);
  EXPECT_TRUE(first["tag"].is_null());
  EXPECT_TRUE(first["triangle"].is_number_integer());

  const std::string gpkg = dir_.Path("slope.gpkg");
  const auto j = Json(RunCli("measure slope --json " + s_ + " --surface plane -o " + Quote(gpkg)));
  EXPECT_EQ(j["triangles"], 64);
  const std::string info = Ogrinfo(gpkg);
  EXPECT_NE(info.find("Layer name: slope"), std::string::npos) << info;
  EXPECT_NE(info.find("Geometry: 3D Polygon"), std::string::npos) << info;
  EXPECT_NE(info.find("Feature Count: 64"), std::string::npos) << info;
  EXPECT_NE(info.find("slope_deg: Real"), std::string::npos) << info;
  EXPECT_NE(info.find("aspect_deg: Real"), std::string::npos) << info;
  const std::string values = RunTool("ogrinfo -ro -al -q " + Quote(gpkg) + " -fid 1");
  EXPECT_NE(values.find("aspect_deg (Real) = 270"), std::string::npos) << values;
}

// The bowl z = r^2 / 100 at levels 3 + 10 k: circles of radius 17, 36 and 48 m inside the 50 m
// half-width, then four corner arcs at each of 33 and 43: 11 lines at 5 levels, in any format.
TEST_F(MeasureCliTest, ContoursAreReadByOgrinfoInEachFormat) {
  for (const char* name : {"c.gpkg", "c.geojson", "c.shp"}) {
    SCOPED_TRACE(name);
    const std::string out = dir_.Path(name);
    const auto j = Json(RunCli("contours --json " + s_ +
                               " --surface bowl --interval 10 --base 3 -o " + Quote(out)));
    EXPECT_EQ(j["lines"], 11);
    EXPECT_EQ(j["closed"], 3);
    EXPECT_EQ(j["levels"], 5);
    EXPECT_EQ(j["min_level"], 3);
    EXPECT_EQ(j["max_level"], 43);
    const std::string info = Ogrinfo(out);
    EXPECT_NE(info.find("Feature Count: 11"), std::string::npos) << info;
    EXPECT_NE(info.find("elevation: Real"), std::string::npos) << info;
    EXPECT_NE(info.find("3D Line String"), std::string::npos) << info;
    EXPECT_NE(info.find("32632"), std::string::npos) << info;  // the CRS came along
    // The elevation of every feature, as ogrinfo prints it.
    const std::string rows = RunTool("ogrinfo -ro -al -q " + Quote(out));
    std::set<double> levels;
    const std::string field = "elevation (Real) = ";
    for (size_t at = rows.find(field); at != std::string::npos; at = rows.find(field, at + 1)) {
      levels.insert(std::strtod(rows.c_str() + at + field.size(), nullptr));
    }
    EXPECT_EQ(levels, (std::set<double>{3, 13, 23, 33, 43}));
  }
  // No temporary directory or partial file is left beside the outputs.
  for (const auto& entry : std::filesystem::directory_iterator(dir_.dir())) {
    const std::string file = entry.path().filename().string();
    EXPECT_EQ(file.find("partial"), std::string::npos) << file;
    EXPECT_NE(file.rfind(".tinbase-", 0), 0u) << file;
  }
}

TEST_F(MeasureCliTest, ContoursBadInputLeavesNoFile) {
  const std::string txt = dir_.Path("c.txt");
  ExpectRejected(store_, "contours " + s_ + " --surface bowl --interval 10 -o " + Quote(txt),
                 "unknown format");
  EXPECT_FALSE(std::filesystem::exists(txt));
  const std::string gpkg = dir_.Path("c.gpkg");
  ExpectRejected(store_, "contours " + s_ + " --surface bowl --interval 0 -o " + Quote(gpkg),
                 "contour interval must be a positive number");
  ExpectRejected(store_, "contours " + s_ + " --surface bowl --interval nan -o " + Quote(gpkg),
                 "contour interval must be a positive number");
  ExpectRejected(store_,
                 "contours " + s_ + " --surface bowl --interval 100 --base 60 -o " + Quote(gpkg),
                 "no contour line");
  EXPECT_FALSE(std::filesystem::exists(gpkg));
  const std::string unwritable = dir_.Path("no/such/dir/c.gpkg");
  ExpectRejected(store_, "contours " + s_ + " --surface bowl --interval 10 -o " + Quote(unwritable),
                 "no/such/dir");
  const std::string shp = dir_.Path("no/such/dir/c.shp");
  ExpectRejected(store_, "contours " + s_ + " --surface bowl --interval 10 -o " + Quote(shp),
                 "no/such/dir");
  ExpectRejected(store_, "measure slope " + s_ + " --surface plane -o " + Quote(dir_.Path("s.csv")),
                 "unknown format");
  for (const auto& entry : std::filesystem::directory_iterator(dir_.dir())) {
    const std::string file = entry.path().filename().string();
    EXPECT_TRUE(file.rfind("m.tinbase", 0) == 0) << "left behind: " << file;
  }
}

// A store in longitude / latitude (EPSG:4326): plan areas are geodesic on WGS 84. The grid's
// triangles have geodesic edges, so their areas add up to the geodesic polygon through the
// grid's boundary vertices, which GeographicLib computes here directly. A surface rising 1 m
// per 100 m northwards has slope atan(0.01) facing south.
TEST(MeasureCliGeographicTest, AreasAreGeodesic) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "g.tinbase");
  const int n = 4;
  const double lon0 = 10, lat0 = 45, step = 0.0025;
  const double metres_per_degree_lat = 111132.0;  // near 45 N; the slope is checked loosely
  {
    auto s = Store::Create(store, "EPSG:4326");
    ASSERT_TRUE(s.ok()) << s.status().ToString();
    MeasureCliTest::Add(**s, "g",
                        testing::GridTin(n, n, lon0, lat0, lon0 + n * step, lat0 + n * step,
                                         [&](double, double lat) {
                                           return (lat - lat0) * metres_per_degree_lat / 100;
                                         }));
  }
  const GeographicLib::Geodesic& wgs84 = GeographicLib::Geodesic::WGS84();
  GeographicLib::PolygonArea boundary(wgs84);
  for (int i = 0; i < n; ++i) boundary.AddPoint(lat0, lon0 + i * step);
  for (int j = 0; j < n; ++j) boundary.AddPoint(lat0 + j * step, lon0 + n * step);
  for (int i = n; i > 0; --i) boundary.AddPoint(lat0 + n * step, lon0 + i * step);
  for (int j = n; j > 0; --j) boundary.AddPoint(lat0 + j * step, lon0);
  double perimeter = 0, want = 0;
  boundary.Compute(false, true, perimeter, want);
  const auto j = Json(RunCli("measure area --json " + Quote(store) + " --surface g"));
  EXPECT_EQ(j["plan_area"], "geodesic");
  EXPECT_NEAR(j["total"]["plan_m2"].get<double>(), want, 1e-9 * want);
  EXPECT_NEAR(j["total"]["surface_m2"].get<double>(), want * std::sqrt(1 + 1e-4), 1e-4 * want);
  CliResult slope = RunCli("measure slope --json " + Quote(store) + " --surface g");
  ASSERT_EQ(slope.exit_code, 0) << slope.err;
  std::istringstream lines(slope.out);
  std::string line;
  while (std::getline(lines, line)) {
    const auto t = nlohmann::json::parse(line);
    EXPECT_NEAR(t["slope_deg"].get<double>(), std::atan(0.01) * 180 / M_PI, 2e-3);
    EXPECT_NEAR(t["aspect_deg"].get<double>(), 180, 0.5);
  }
}

// On a store built from a real DEM: a stored fill polygon gives per-tag areas, and cut/fill
// inside it equals cut/fill inside the same polygon read from its file.
TEST(MeasureCliDemTest, StoredFeatureMeasuresAsItsFile) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "d.tinbase");
  const std::string s = Quote(store);
  RunWrite(store, "init " + s);
  RunWrite(store, "dem import " + s + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
  RunWrite(store, "tin build " + s + " --surface fine --tolerance 10");
  RunWrite(store, "tin build " + s + " --surface coarse --tolerance 40");
  const double x = 535000, y = 7500000;
  const std::string square =
      Square(dir, "pit.geojson", x - 3000, y - 2000, x + 3000, y + 2000, 28350);
  RunWrite(store,
           "polygon add " + s + " " + Quote(square) + " --surface fine --mode fill --tag pit");
  const auto area = Json(RunCli("measure area --json " + s + " --surface fine"));
  bool found = false;
  for (const auto& t : area["tags"]) {
    if (t["tag"] != "pit") continue;
    found = true;
    EXPECT_NEAR(t["plan_m2"].get<double>(), 6000.0 * 4000, 1e-3);
  }
  EXPECT_TRUE(found) << area.dump();
  const auto by_feature =
      Json(RunCli("measure cutfill --json " + s + " --base coarse --top fine --feature 1"));
  const auto by_file = Json(RunCli("measure cutfill --json " + s +
                                   " --base coarse --top fine --polygon " + Quote(square)));
  for (const char* key : {"cut_m3", "fill_m3", "plan_area_m2"}) {
    EXPECT_NEAR(by_feature[key].get<double>(), by_file[key].get<double>(),
                1e-9 * std::abs(by_file[key].get<double>()) + 1e-6)
        << key;
  }
  EXPECT_NEAR(by_file["plan_area_m2"].get<double>(), 6000.0 * 4000, 1e-3);
  EXPECT_GT(by_file["cut_m3"].get<double>() + by_file["fill_m3"].get<double>(), 0);
  // The feature's own inside as a selection: the volume of the tagged part.
  const auto v =
      Json(RunCli("measure volume --json " + s + " --surface fine --feature 1 --level 0"));
  EXPECT_NEAR(v["plan_area_m2"].get<double>(), 6000.0 * 4000, 1e-3);
  EXPECT_EQ(Json(RunCli("measure volume --json " + s +
                        " --surface fine --tag pit --level 0"))["above_m3"],
            v["above_m3"]);
}

}  // namespace
}  // namespace tinbase
