// The query commands end to end through the tinbase binary: `locate --points` streaming CSV and
// JSON lines from files, standard input and OGR layers, `star`, `triangles`, `neighbours` with
// the shared edges, and `profile` with its PNG plot (read back by gdalinfo); on a stored plane,
// whose z is known everywhere, and on the Hamersley terrain for a feature. Bad input is refused
// with one line naming the problem, no output and no file left behind.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/db/query/query_fixture.h"
#include "tests/support/cli_support.h"
#include "tests/support/grid_tin.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::CliResult;
using testing::DataPath;
using testing::ExpectRejected;
using testing::Json;
using testing::PlaneZ;
using testing::Quote;
using testing::RunCli;
using testing::RunWrite;
using testing::StoreTarget;
using testing::TempDir;

constexpr double kX0 = 500000, kY0 = 5000000;

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::vector<std::string> Split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, ',');) out.push_back(field);
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

// Runs a shell command, returning its exit code and standard output (RunCli's standard input is
// /dev/null, so piping into tinbase needs its own shell).
std::pair<int, std::string> Shell(const std::string& command, const TempDir& dir) {
  const std::string out = dir.Path("shell.out");
  const int status = std::system((command + " >" + Quote(out) + " 2>/dev/null").c_str());
  std::ifstream in(out);
  std::stringstream text;
  text << in.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128, text.str()};
}

// A 20 x 10 grid of 10 m cells on the plane PlaneZ, west half tagged "sand", east half "clay".
class QueryCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    Tin tin = testing::MakeGridTin(20, 10, 10, kX0, kY0, PlaneZ);
    tin.tags = {"sand", "clay"};
    for (TinTriangle& t : tin.triangles)
      t.tag =
          tin.vertices[t.v[0]].x + tin.vertices[t.v[1]].x + tin.vertices[t.v[2]].x < 3 * (kX0 + 100)
              ? 0
              : 1;
    store_ = StoreTarget(dir_, "plane.tinbase");
    auto stored = testing::StoreSurface(store_, "plane", tin);
    ASSERT_TRUE(stored.ok()) << stored.status().ToString();
  }

  std::string Cmd(const std::string& command) const {
    return command + " " + Quote(store_) + " --surface plane ";
  }

  TempDir dir_;
  std::string store_;
};

TEST_F(QueryCliTest, LocatePointsStreamsCsvRowsOnThePlane) {
  const std::string file = dir_.Path("pts.txt");
  std::ofstream(file) << "# x y\n500012.5 5000031.25\n\n500150,5000050\n1 2\n500199.5 5000099.5\n";
  const CliResult r = RunCli(Cmd("locate") + "--points " + Quote(file));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto lines = Lines(r.out);
  ASSERT_EQ(lines.size(), 5u) << r.out;
  EXPECT_EQ(lines[0], "x,y,triangle,z,visible,tag");
  const double xs[] = {500012.5, 500150, 1, 500199.5}, ys[] = {5000031.25, 5000050, 2, 5000099.5};
  for (size_t i = 0; i < 4; ++i) {
    const auto f = Split(lines[i + 1]);
    ASSERT_EQ(f.size(), 6u) << lines[i + 1];
    EXPECT_EQ(std::stod(f[0]), xs[i]);
    EXPECT_EQ(std::stod(f[1]), ys[i]);
    if (i == 2) {  // outside: no triangle, z, visibility or tag
      EXPECT_EQ(lines[i + 1], "1,2,,,,");
      continue;
    }
    EXPECT_FALSE(f[2].empty());
    EXPECT_NEAR(std::stod(f[3]), PlaneZ(xs[i], ys[i]), 1e-9);
    EXPECT_EQ(f[4], "true");
    EXPECT_EQ(f[5], xs[i] < kX0 + 100 ? "sand" : "clay");
  }
}

TEST_F(QueryCliTest, LocatePointsReadsJsonLinesCsvHeadersStdinAndOgrLayers) {
  const std::string csv = dir_.Path("pts.csv");
  std::ofstream(csv) << "id,northing,easting\n1,5000031.25,500012.5\n2,5000050,500150\n";
  const CliResult r = RunCli(Cmd("locate") + "--json --points " + Quote(csv));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto lines = Lines(r.out);
  ASSERT_EQ(lines.size(), 2u) << r.out;
  const auto first = nlohmann::json::parse(lines[0]);
  EXPECT_EQ(first["x"], 500012.5);
  EXPECT_EQ(first["y"], 5000031.25);
  EXPECT_NEAR(first["z"].get<double>(), PlaneZ(500012.5, 5000031.25), 1e-9);
  EXPECT_EQ(first["tag"], "sand");
  EXPECT_TRUE(first["visible"].get<bool>());
  EXPECT_TRUE(first["triangle"].is_number_integer());
  EXPECT_EQ(nlohmann::json::parse(lines[1])["tag"], "clay");

  // The same points from standard input give the same answers.
  const auto [code, out] =
      Shell("printf '500012.5 5000031.25\\n500150 5000050\\n' | " + std::string(TINBASE_CLI) + " " +
                Cmd("locate") + "--json --points -",
            dir_);
  EXPECT_EQ(code, 0);
  EXPECT_EQ(out, r.out);

  // A GeoJSON point layer (reprojection is point_input_test's).
  const std::string geojson = dir_.Path("pts.geojson");
  std::ofstream(geojson)
      << R"({"type":"FeatureCollection","crs":{"type":"name","properties":{"name":"EPSG:32632"}},)"
      << R"("features":[{"type":"Feature","properties":{},"geometry":{"type":"Point",)"
      << R"("coordinates":[500100,5000050]}}]})";
  const CliResult g = RunCli(Cmd("locate") + "--json --points " + Quote(geojson));
  ASSERT_EQ(g.exit_code, 0) << g.err;
  EXPECT_NEAR(nlohmann::json::parse(g.out)["z"].get<double>(), PlaneZ(500100, 5000050), 1e-9);

  // The single point form is unchanged.
  const auto one = Json(RunCli(Cmd("locate") + "--json -- 500012.5 5000031.25"));
  EXPECT_EQ(one["triangle"], first["triangle"]);
  EXPECT_EQ(one["surface"], "plane");
  EXPECT_GE(one["steps"].get<int>(), 1);
}

TEST_F(QueryCliTest, AMalformedPointFileIsRefusedNamingTheLineWithNoOutput) {
  const std::string file = dir_.Path("bad.txt");
  std::ofstream(file) << "500012.5 5000031.25\n500150 5000050\n500150 50000x0\n";
  const CliResult r = RunCli(Cmd("locate") + "--points " + Quote(file));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.out, "");  // not even the header: the file is checked before any answer
  EXPECT_NE(r.err.find("bad.txt:3: '50000x0' is not a number"), std::string::npos) << r.err;
  const auto [code, out] = Shell("printf '1 2\\nthree 4\\n' | " + std::string(TINBASE_CLI) + " " +
                                     Cmd("locate") + "--points -",
                                 dir_);
  EXPECT_NE(code, 0);
  EXPECT_EQ(out, "");
  ExpectRejected(store_, Cmd("locate") + "--points " + Quote(dir_.Path("none.txt")), "none.txt");
  ExpectRejected(store_, Cmd("locate") + "--points " + Quote(file) + " -- 1 2", "not both");
  ExpectRejected(store_, Cmd("locate"), "give x y, or --points");
}

TEST_F(QueryCliTest, StarTrianglesAndNeighboursOfTheGrid) {
  // The vertex at grid node (2, 2): its four cells all have their diagonal through it (their
  // i + j is even or their diagonal runs b-d to it), eight triangles in all.
  const auto where = Json(RunCli(Cmd("locate") + "--json -- 500020 5000020"));
  const auto nb = Json(RunCli(Cmd("neighbours") + "--json " + where["triangle"].dump()));
  ASSERT_EQ(nb["edges"].size(), 3u);
  int64_t vertex = 0;
  for (const auto& e : nb["edges"]) {
    EXPECT_EQ(e["from"][2].get<double>(),
              PlaneZ(e["from"][0].get<double>(), e["from"][1].get<double>()));
    if (e["from"][0] == 500020.0 && e["from"][1] == 5000020.0) vertex = e["vertices"][0];
    // Each neighbour has this edge too, the other way round.
    if (e["neighbour"].is_null()) continue;
    const auto other = Json(RunCli(Cmd("neighbours") + "--json " + e["neighbour"].dump()));
    bool shared = false;
    for (const auto& o : other["edges"])
      shared |= o["vertices"][0] == e["vertices"][1] && o["vertices"][1] == e["vertices"][0] &&
                o["neighbour"] == nb["triangle"];
    EXPECT_TRUE(shared) << e.dump();
  }
  ASSERT_NE(vertex, 0);
  const auto star = Json(RunCli(Cmd("star") + "--json " + std::to_string(vertex)));
  EXPECT_EQ(star["vertex"], vertex);
  EXPECT_FALSE(star["boundary"].get<bool>());
  EXPECT_EQ(star["triangles"].size(), 8u);
  EXPECT_EQ(star["links"].size(), 8u);
  EXPECT_EQ(star["z"].get<double>(), PlaneZ(500020, 5000020));
  EXPECT_NE(std::find(star["triangles"].begin(), star["triangles"].end(), where["triangle"]),
            star["triangles"].end());

  // A window inside one cell meets its two triangles, all of whose corners are the cell's.
  const auto cell = Json(RunCli(Cmd("triangles") + "--json --bbox 500012,5000012,500018,5000018"));
  ASSERT_EQ(cell["count"], 2);
  for (const auto& t : cell["triangles"])
    for (const auto& c : t["corners"]) {
      EXPECT_TRUE(c[0] == 500010.0 || c[0] == 500020.0) << c.dump();
      EXPECT_TRUE(c[1] == 5000010.0 || c[1] == 5000020.0) << c.dump();
      EXPECT_EQ(c[2].get<double>(), PlaneZ(c[0].get<double>(), c[1].get<double>()));
    }
  const auto tagged =
      Json(RunCli(Cmd("triangles") + "--json --bbox 500000,5000000,500200,5000100 --tag clay"));
  EXPECT_EQ(tagged["count"], 200);  // the east half: 10 x 10 cells
  const CliResult text = RunCli(Cmd("triangles") + "--bbox 500012,5000012,500018,5000018");
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_EQ(Lines(text.out).size(), 3u) << text.out;

  ExpectRejected(store_, Cmd("triangles") + "--bbox 0,0,10,10", "nothing selected");
  ExpectRejected(store_, Cmd("triangles") + "--bbox 0,0,10", "--bbox");
  ExpectRejected(store_, Cmd("triangles"), "give --bbox");
  ExpectRejected(store_, Cmd("star") + "987654", "987654");
  ExpectRejected(store_, Cmd("neighbours") + "987654", "987654");
}

TEST_F(QueryCliTest, ProfileCsvJsonAndAPlotGdalReads) {
  const std::string line = "--line '500005,5000005 500195,5000095 500195.5,5000003' ";
  const CliResult csv = RunCli(Cmd("profile") + line);
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  const auto rows = Lines(csv.out);
  ASSERT_GT(rows.size(), 40u);
  EXPECT_EQ(rows[0], "distance,x,y,z,kind,triangle,visible,tag");
  double last = -1;
  for (size_t i = 1; i < rows.size(); ++i) {
    const auto f = Split(rows[i]);
    ASSERT_EQ(f.size(), 8u) << rows[i];
    EXPECT_GE(std::stod(f[0]), last);
    last = std::stod(f[0]);
    EXPECT_NEAR(std::stod(f[3]), PlaneZ(std::stod(f[1]), std::stod(f[2])), 1e-9) << rows[i];
    if (i + 1 < rows.size()) {
      EXPECT_TRUE(f[7] == "sand" || f[7] == "clay") << rows[i];
    }
  }
  EXPECT_EQ(Split(rows[1])[4], "start");
  EXPECT_EQ(Split(rows.back())[4], "end");
  EXPECT_EQ(rows.back().substr(rows.back().size() - 3), ",,,");  // no stretch after the end
  EXPECT_NEAR(last, std::hypot(190, 90) + std::hypot(0.5, 92), 1e-9);

  const std::string png = dir_.Path("profile.png");
  const auto json = Json(RunCli(Cmd("profile") + line + "--json --plot " + Quote(png)));
  EXPECT_EQ(json["stations"].size() - 1, json["stretches"].size());
  EXPECT_EQ(json["stations"].size() + 1, rows.size());
  EXPECT_NEAR(json["length"].get<double>(), last, 1e-9);
  EXPECT_EQ(json["stretches"][0]["tag"], "sand");
  EXPECT_EQ(json["stretches"].back()["tag"], "clay");
  const CliResult info = [&] {
    CliResult r;
    auto [code, out] = Shell("gdalinfo -json " + Quote(png), dir_);
    r.exit_code = code;
    r.out = out;
    return r;
  }();
  ASSERT_EQ(info.exit_code, 0) << "gdalinfo (GDAL's command-line tools) must read the plot";
  const auto doc = nlohmann::json::parse(info.out);
  EXPECT_EQ(doc["driverShortName"], "PNG");
  EXPECT_EQ(doc["size"], nlohmann::json::array({1000, 400}));
  EXPECT_EQ(doc["bands"].size(), 3u);

  // The line from a GeoJSON LineString in the store's CRS (GeoJSON without one is WGS 84).
  const std::string geojson = dir_.Path("line.geojson");
  std::ofstream(geojson) << R"({"type":"FeatureCollection","crs":{"type":"name","properties":)"
                         << R"({"name":"EPSG:32632"}},"features":[{"type":"Feature",)"
                         << R"("properties":{},"geometry":{"type":"LineString","coordinates":)"
                         << R"([[500005,5000005],[500195,5000095],[500195.5,5000003]]}}]})";
  const CliResult from_file = RunCli(Cmd("profile") + "--line-file " + Quote(geojson));
  EXPECT_EQ(from_file.exit_code, 0) << from_file.err;
  EXPECT_EQ(from_file.out, csv.out);
}

TEST_F(QueryCliTest, BadProfilesAreRefusedAndLeaveNoPlot) {
  const std::string png = dir_.Path("p.png");
  ExpectRejected(store_, Cmd("profile") + "--line 500005,5000005 --plot " + Quote(png),
                 "a profile line needs at least two points, got 1");
  ExpectRejected(store_, Cmd("profile") + "--line '500005,5000005 9e9,1' --plot " + Quote(png),
                 "the line leaves the surface at");
  ExpectRejected(store_, Cmd("profile") + "--line '500005,5000005 x,1'", "point 2 'x,1'");
  ExpectRejected(store_, Cmd("profile") + "--line '1,1 500005,5000005'",
                 "profile point 1: point (1, 1) is outside surface 'plane'");
  ExpectRejected(store_, Cmd("profile"), "--line");
  ExpectRejected(
      store_,
      Cmd("profile") + "--line '500005,5000005 500100,5000050' --width 10 --plot " + Quote(png),
      "200 x 100 to 16384 x 16384 pixels, not 10 x 400");
  EXPECT_FALSE(std::filesystem::exists(png));
  const std::string unwritable = dir_.Path("no/such/dir/p.png");
  ExpectRejected(
      store_, Cmd("profile") + "--line '500005,5000005 500100,5000050' --plot " + Quote(unwritable),
      "--plot");
  // No temporary file is left beside the plot either.
  for (const auto& entry : std::filesystem::directory_iterator(dir_.dir()))
    EXPECT_EQ(entry.path().filename().string().find("p.png"), std::string::npos) << entry.path();
}

// Hamersley terrain with a square fill feature: `triangles --feature` lists the triangles inside
// it, each centroid within the square.
TEST(QueryCliStandalone, TrianglesOfAFeature) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "h.tinbase");
  RunWrite(store, "init " + Quote(store));
  RunWrite(store,
           "dem import " + Quote(store) + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
  RunWrite(store, "tin build " + Quote(store) + " --surface terrain --tolerance 10");
  const std::string square = dir.Path("square.geojson");
  std::ofstream(square) << R"({"type":"FeatureCollection","crs":{"type":"name","properties":)"
                        << R"({"name":"EPSG:28350"}},"features":[{"type":"Feature","properties":)"
                        << R"({},"geometry":{"type":"Polygon","coordinates":[[[520000,7480000],)"
                        << R"([525000,7480000],[525000,7485000],[520000,7485000],)"
                        << R"([520000,7480000]]]}}]})";
  RunWrite(store, "polygon add " + Quote(store) + " " + Quote(square) +
                      " --surface terrain --mode fill --tag granite");
  const auto j =
      Json(RunCli("triangles --json " + Quote(store) + " --surface terrain --feature 1"));
  EXPECT_EQ(j["filter"], "feature 1");
  ASSERT_GT(j["count"].get<int>(), 20);
  double area = 0;
  for (const auto& t : j["triangles"]) {
    double cx = 0, cy = 0;
    for (const auto& c : t["corners"]) cx += c[0].get<double>() / 3, cy += c[1].get<double>() / 3;
    EXPECT_GT(cx, 520000);
    EXPECT_LT(cx, 525000);
    EXPECT_GT(cy, 7480000);
    EXPECT_LT(cy, 7485000);
    EXPECT_EQ(t["tag"], "granite");
    const auto& c = t["corners"];
    area += ((c[1][0].get<double>() - c[0][0].get<double>()) *
                 (c[2][1].get<double>() - c[0][1].get<double>()) -
             (c[1][1].get<double>() - c[0][1].get<double>()) *
                 (c[2][0].get<double>() - c[0][0].get<double>())) /
            2;
  }
  // The ring is constrained, so the triangles tile the square exactly.
  EXPECT_NEAR(area, 5000.0 * 5000.0, 1e-3);
  ExpectRejected(store, "triangles " + Quote(store) + " --surface terrain --feature 99", "99");
}

}  // namespace
}  // namespace tinbase
