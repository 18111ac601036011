// `tinbase points add` and `points remove` end to end on the Hamersley DEM: survey points from
// CSV and GeoJSON go in and come out again with `check --full` passing after every write, and bad
// input (a point outside, a point without z, NaN, a polygon feature) is refused with one line
// naming it and the store unchanged; with --update-tiles the tiles commit with the edit.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "db/store.h"
#include "tests/support/cli_support.h"
#include "tests/support/store_target.h"
#include "tests/support/store_template.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::ExpectRejected;
using testing::Json;
using testing::Quote;
using testing::RunCli;
using testing::RunWrite;
using testing::StoreTarget;
using testing::TempDir;

// The Hamersley DEM's centre (EPSG:28350) and cell size.
constexpr double kCx = 539300, kCy = 7497340, kCell = 344.404386931320971;

class PointsEditCli : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    testing::CopyRecipeStore(testing::HamersleyTerrainRecipe(5), store_);
  }

  // A CSV of an n x n grid of shots 3.3 cells apart around the centre, z from the DEM + 2.
  std::string GridCsv(int n) {
    const std::string path = dir_.Path("shots.csv");
    std::ofstream out(path);
    out << "x,y,z\n";
    const int half = n / 2;  // the grid's middle shot is the centre's
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const double x = kCx + (i - half) * 3.3 * kCell + 0.37;
        const double y = kCy + (j - half) * 3.3 * kCell + 0.61;
        auto z = RunCli("dem sample --json " + Quote(store_) + " -- " + std::to_string(x) + " " +
                        std::to_string(y));
        const nlohmann::json j_z = nlohmann::json::parse(z.out);
        const double dem_z = j_z.is_array() ? j_z[0]["z"].get<double>() : j_z["z"].get<double>();
        out.precision(17);
        out << x << "," << y << "," << dem_z + 2 << "\n";
      }
    }
    return path;
  }

  std::string Write(const std::string& name, const std::string& text) {
    const std::string path = dir_.Path(name);
    std::ofstream(path) << text;
    return path;
  }

  TempDir dir_;
  std::string store_;
};

TEST_F(PointsEditCli, AddThenRemoveByBoxAndByFeatureEachPassCheck) {
  const std::string csv = GridCsv(4);
  auto add =
      RunWrite(store_, "points add --json " + Quote(store_) + " --surface terrain " + Quote(csv));
  const nlohmann::json report = Json(add);
  EXPECT_EQ(report["points_in"], 16);
  EXPECT_EQ(report["vertices"], 16);
  EXPECT_TRUE(report["snapped"].empty());
  const int64_t feature = report["features_added"][0].get<int64_t>();

  auto changes = Json(RunCli("changes --json " + Quote(store_) + " --since 0"));
  EXPECT_NE(changes.dump().find("points add"), std::string::npos) << changes.dump();

  // The left half of the grid by box: the right half stays as a new feature.
  const std::string box =
      std::to_string(kCx - 10 * kCell) + "," + std::to_string(kCy - 10 * kCell) + "," +
      std::to_string(kCx - 0.5 * kCell) + "," + std::to_string(kCy + 10 * kCell);
  auto by_box = Json(RunWrite(
      store_, "points remove --json " + Quote(store_) + " --surface terrain --bbox " + box));
  EXPECT_EQ(by_box["vertices"], 8);
  EXPECT_EQ(by_box["features_removed"][0], feature);
  const int64_t rest = by_box["features_added"][0].get<int64_t>();
  auto by_feature = Json(RunWrite(
      store_, "points remove --json " + Quote(store_) + " --feature " + std::to_string(rest)));
  EXPECT_EQ(by_feature["vertices"], 8);
}

TEST_F(PointsEditCli, GeoJsonPointZGoesIn) {
  const std::string geojson = Write(
      "shots.geojson",
      "{\"type\":\"FeatureCollection\",\"crs\":{\"type\":\"name\",\"properties\":{\"name\":"
      "\"urn:ogc:def:crs:EPSG::28350\"}},\"features\":[{\"type\":\"Feature\",\"properties\":{},"
      "\"geometry\":{\"type\":\"MultiPoint\",\"coordinates\":[[539300.5,7497340.5,700.0],"
      "[539900.25,7497000.75,710.0]]}}]}");
  auto add = Json(RunWrite(
      store_, "points add --json " + Quote(store_) + " --surface terrain " + Quote(geojson)));
  EXPECT_EQ(add["vertices"], 2);
  auto locate =
      Json(RunCli("locate --json " + Quote(store_) + " --surface terrain -- 539300.5 7497340.5"));
  EXPECT_NE(locate.dump().find("700"), std::string::npos) << locate.dump();
}

TEST_F(PointsEditCli, BadInputIsRefusedNamingItAndChangesNothing) {
  const std::string store = Quote(store_);
  const std::string outside =
      Write("outside.csv", "x,y,z\n539300.5,7497340.5,700\n9539300.5,7497340.5,700\n");
  ExpectRejected(store_, "points add " + store + " --surface terrain " + Quote(outside),
                 "outside.csv, point 2: (9539300.5, 7497340.5) lies outside surface 'terrain'");
  const std::string nan = Write("nan.csv", "x,y,z\n539300.5,7497340.5,nan\n");
  ExpectRejected(store_, "points add " + store + " --surface terrain " + Quote(nan), "nan.csv");
  const std::string flat =
      Write("flat.geojson",
            "{\"type\":\"FeatureCollection\",\"features\":[{\"type\":\"Feature\",\"properties\":{},"
            "\"geometry\":{\"type\":\"Point\",\"coordinates\":[539300.5,7497340.5]}}]}");
  ExpectRejected(store_, "points add " + store + " --surface terrain " + Quote(flat),
                 "flat.geojson, feature 0: the point has no z");
  ExpectRejected(store_, "points add " + store + " --surface nowhere " + Quote(outside), "nowhere");
  ExpectRejected(store_, "points remove " + store + " --feature 77", "no feature 77");
  ExpectRejected(store_, "points remove " + store + " --bbox 1,2,3", "--bbox");
}

// --update-tiles: the tiles are rewritten inside the edit's own transaction (the change log has
// no transaction of their own, the pyramid's transaction is the edit's, nothing is left for
// `tiles update`), and a tile update that fails rolls the edit back.
TEST_F(PointsEditCli, UpdateTilesCommitsTheTilesWithTheEdit) {
  const std::string store = Quote(store_);
  RunWrite(store_, "tiles build " + store + " --surface terrain --max-zoom 9");
  const std::string csv = GridCsv(2);
  const auto expect_tiles_with = [&](const nlohmann::json& report) {
    EXPECT_GT(report["tiles_updated"].get<int64_t>(), 0) << report.dump();
    const nlohmann::json info = Json(RunCli("tiles info " + store + " --surface terrain --json"));
    EXPECT_EQ(info["layer"]["tinbase"]["tx"], report["tx"]) << info.dump();
    const nlohmann::json changes = Json(RunCli("changes --json " + store));
    EXPECT_EQ(changes.back()["tx"], report["tx"]) << "the tiles made no transaction of their own";
    EXPECT_EQ(Json(RunCli("tiles update " + store + " --surface terrain --json"))["changes"], 0);
  };
  const nlohmann::json add = Json(RunWrite(
      store_, "points add --json --update-tiles " + store + " --surface terrain " + Quote(csv)));
  expect_tiles_with(add);
  const std::string feature = std::to_string(add["features_added"][0].get<int64_t>());

  // A pyramid the update cannot read: the remove is refused and the points stay.
  const auto set_extensions = [&](const std::string& names) {
    auto opened = Store::Open(store_);
    ASSERT_TRUE(opened.ok()) << opened.status().ToString();
    ASSERT_TRUE((*opened)->db().Exec("UPDATE tile_pyramids SET extensions = '" + names + "'").ok());
  };
  set_extensions("bogus");
  ExpectRejected(store_, "points remove --update-tiles " + store + " --feature " + feature,
                 "updating the tiles of the edit: unknown tile extension 'bogus'");
  // Shots beside those in the store (the grid's third row and column): they would go in.
  ExpectRejected(store_,
                 "points add --update-tiles " + store + " --surface terrain " + Quote(GridCsv(3)),
                 "updating the tiles of the edit");
  set_extensions("octvertexnormals");
  expect_tiles_with(Json(
      RunWrite(store_, "points remove --json --update-tiles " + store + " --feature " + feature)));
}

}  // namespace
}  // namespace tinbase
