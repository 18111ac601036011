// `tinbase polygon update` with --z-from and --mode softline, and --update-tiles on polygon add,
// update and remove, end to end on the Hamersley DEM: a 3D line replaced stays 3D unless told
// otherwise, its z is the file's, and the tiles of every edit commit in the edit's own
// transaction (no transaction of their own, nothing left for `tiles update`; a tile update that
// fails rolls the edit back). `check --full` passes after every write; refusals change nothing.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "db/store.h"
#include "tests/support/cli_support.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
#include "tests/support/store_template.h"
#include "tests/support/stored_feature.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::ExpectRejected;
using testing::Json;
using testing::Quote;
using testing::RunCli;
using testing::RunWrite;
using testing::TempDir;

// The Hamersley DEM's centre (EPSG:28350).
constexpr double kCx = 539300, kCy = 7497340;

struct Vertex3 {
  double x, y, z;
};

class PolygonEditCli : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = testing::StoreTarget(dir_, "s.tinbase");
    q_ = Quote(store_);
    testing::CopyRecipeStore(testing::HamersleyTerrainRecipe(5), store_);
  }

  double DemZ(double x, double y) {
    const nlohmann::json j = Json(
        RunCli("dem sample --json " + q_ + " -- " + std::to_string(x) + " " + std::to_string(y)));
    return j.is_array() ? j[0]["z"].get<double>() : j["z"].get<double>();
  }

  // A line from (x0, y0) to (x1, y1) in `n` steps, each vertex `above` metres over the DEM.
  std::vector<Vertex3> Line3(double x0, double y0, double x1, double y1, int n, double above) {
    std::vector<Vertex3> out;
    for (int i = 0; i <= n; ++i) {
      const double x = x0 + (x1 - x0) * i / n + 0.37, y = y0 + (y1 - y0) * i / n + 0.61;
      out.push_back({x, y, DemZ(x, y) + above});
    }
    return out;
  }

  // One LineString feature in EPSG:28350, with z when `with_z`.
  std::string WriteLine(const std::string& name, const std::vector<Vertex3>& line, bool with_z) {
    const std::string path = dir_.Path(name);
    std::ofstream out(path);
    out.precision(17);
    out << R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": )"
        << R"("urn:ogc:def:crs:EPSG::28350"}}, "features": [{"type": "Feature", "properties": )"
        << R"({}, "geometry": {"type": "LineString", "coordinates": [)";
    for (size_t i = 0; i < line.size(); ++i) {
      out << (i ? "," : "") << "[" << line[i].x << "," << line[i].y;
      if (with_z) out << "," << line[i].z;
      out << "]";
    }
    out << "]}}]}\n";
    return path;
  }

  EditorFeature Load(int64_t id) { return testing::LoadStoredFeature(store_, "terrain", id); }

  // The constraint rows of `feature` of `kind` ('hard' or 'soft').
  int64_t Constraints(int64_t feature, const std::string& kind) {
    auto store = Store::Open(store_, Store::Access::kReadOnly);
    EXPECT_TRUE(store.ok()) << store.status().ToString();
    auto count = (*store)->db().Prepare("SELECT count(*) FROM constraints WHERE feature = " +
                                        std::to_string(feature) + " AND kind = '" + kind + "'");
    EXPECT_TRUE(count.ok()) << count.status().ToString();
    auto row = (*count)->Step();
    EXPECT_TRUE(row.ok() && *row);
    return (*count)->ColumnInt(0);
  }

  // The id of the feature `polygon update` printed as the new geometry.
  static int64_t NewFeature(const testing::CliResult& r) {
    const std::string key = "the new geometry is feature ";
    const size_t at = r.out.find(key);
    EXPECT_NE(at, std::string::npos) << r.out;
    return at == std::string::npos ? 0 : std::stoll(r.out.substr(at + key.size()));
  }

  static void ExpectOwnZ(const EditorFeature& f, const std::vector<Vertex3>& line) {
    EXPECT_EQ(f.z_from, ZFrom::kFeature);
    ASSERT_EQ(f.line_z.size(), 1u);
    ASSERT_EQ(f.line_z[0].size(), line.size());
    for (size_t i = 0; i < line.size(); ++i) EXPECT_EQ(f.line_z[0][i], line[i].z) << i;
  }

  TempDir dir_;
  std::string store_, q_;
};

TEST_F(PolygonEditCli, UpdateKeepsAThreeDLineThreeDAndTakesZFromAndSoftline) {
  const auto first = Line3(kCx - 2000, kCy - 1500, kCx + 2000, kCy + 1200, 4, 3);
  const nlohmann::json added = Json(RunWrite(
      store_, "polygon add --json " + q_ + " " + Quote(WriteLine("a.geojson", first, true)) +
                  " --surface terrain --mode breakline --z-from feature"));
  const int64_t id = added["features"][0].get<int64_t>();
  ExpectOwnZ(Load(id), first);

  // Without --z-from the replacement keeps its z from the feature, as the old line did.
  const auto second = Line3(kCx - 1800, kCy + 1500, kCx + 1900, kCy - 1300, 5, -2);
  const int64_t kept =
      NewFeature(RunWrite(store_, "polygon update " + q_ + " " + std::to_string(id) + " " +
                                      Quote(WriteLine("b.geojson", second, true))));
  const EditorFeature k = Load(kept);
  EXPECT_EQ(k.mode, FeatureMode::kBreakline);
  ExpectOwnZ(k, second);

  // --z-from dem and --mode softline: draped, soft.
  const int64_t draped = NewFeature(RunWrite(
      store_, "polygon update " + q_ + " " + std::to_string(kept) + " " +
                  Quote(WriteLine("c.geojson", second, false)) + " --z-from dem --mode softline"));
  const EditorFeature d = Load(draped);
  EXPECT_EQ(d.mode, FeatureMode::kSoftline);
  EXPECT_EQ(d.z_from, ZFrom::kDem);
  EXPECT_TRUE(d.line_z.empty());

  // And back to 3D, still soft (the mode is kept).
  const int64_t again = NewFeature(
      RunWrite(store_, "polygon update " + q_ + " " + std::to_string(draped) + " " +
                           Quote(WriteLine("d.geojson", first, true)) + " --z-from feature"));
  EXPECT_EQ(Load(again).mode, FeatureMode::kSoftline);
  ExpectOwnZ(Load(again), first);
  EXPECT_GT(Constraints(again, "soft"), 0);
  EXPECT_EQ(Constraints(again, "hard"), 0);
}

TEST_F(PolygonEditCli, BadZFromOnUpdateIsRefusedAndChangesNothing) {
  const auto line = Line3(kCx - 2000, kCy - 1500, kCx + 2000, kCy + 1200, 4, 3);
  const std::string line3 = Quote(WriteLine("a.geojson", line, true));
  const std::string line2 = Quote(WriteLine("flat.geojson", line, false));
  const nlohmann::json added = Json(RunWrite(store_, "polygon add --json " + q_ + " " + line3 +
                                                         " --surface terrain --mode breakline "
                                                         "--z-from feature"));
  const std::string id = std::to_string(added["features"][0].get<int64_t>());
  ExpectRejected(store_, "polygon update " + q_ + " " + id + " " + line3 + " --z-from top",
                 "--z-from: unknown z source 'top'");
  // The old line is 3D: a file without z needs --z-from dem.
  ExpectRejected(store_, "polygon update " + q_ + " " + id + " " + line2,
                 "--z-from feature needs lines with z");
  const std::string square = Quote(
      testing::WritePolygons(dir_, "square.geojson", {{testing::Ngon(kCx + 5000, kCy, 900, 4)}}));
  const nlohmann::json fill = Json(RunWrite(
      store_, "polygon add --json " + q_ + " " + square + " --surface terrain --mode fill"));
  ExpectRejected(store_,
                 "polygon update " + q_ + " " + std::to_string(fill["features"][0].get<int64_t>()) +
                     " " + square + " --z-from feature",
                 "--z-from feature is for lines");
}

// Each edit with --update-tiles: its transaction is the pyramid's, the change log has no other,
// and `tiles update` finds nothing left; a tile update that fails refuses the edit.
TEST_F(PolygonEditCli, UpdateTilesCommitsTheTilesWithEachEdit) {
  RunWrite(store_, "tiles build " + q_ + " --surface terrain --max-zoom 9");
  const auto expect_tiles_with = [&](int64_t tx) {
    const nlohmann::json info = Json(RunCli("tiles info " + q_ + " --surface terrain --json"));
    EXPECT_EQ(info["layer"]["tinbase"]["tx"], tx) << info.dump();
    const nlohmann::json changes = Json(RunCli("changes --json " + q_));
    EXPECT_EQ(changes.back()["tx"], tx) << "the tiles made no transaction of their own";
    EXPECT_EQ(Json(RunCli("tiles update " + q_ + " --surface terrain --json"))["changes"], 0);
  };
  const auto last_tx = [&] { return Json(RunCli("changes --json " + q_)).back()["tx"]; };
  const std::string squares = Quote(testing::WritePolygons(
      dir_, "squares.geojson",
      {{testing::Ngon(kCx, kCy, 900, 4)}, {testing::Ngon(kCx + 4000, kCy, 900, 4)}}));
  const nlohmann::json added =
      Json(RunWrite(store_, "polygon add --json --update-tiles " + q_ + " " + squares +
                                " --surface terrain --mode fill --tag lake"));
  EXPECT_GT(added["tiles_updated"].get<int64_t>(), 0);
  expect_tiles_with(added["tx"].get<int64_t>());

  // --each: every feature's transaction carries its own tiles.
  const std::string more = Quote(testing::WritePolygons(
      dir_, "more.geojson",
      {{testing::Ngon(kCx, kCy + 5000, 900, 5)}, {testing::Ngon(kCx + 4000, kCy + 5000, 900, 5)}}));
  const testing::CliResult each = RunWrite(store_, "polygon add --each --update-tiles " + q_ + " " +
                                                       more + " --surface terrain --mode erase");
  EXPECT_NE(each.out.find("tiles of 'terrain': "), std::string::npos) << each.out;
  expect_tiles_with(last_tx().get<int64_t>());

  const std::string id = std::to_string(added["features"][0].get<int64_t>());
  const std::string moved = Quote(testing::WritePolygons(
      dir_, "moved.geojson", {{testing::Ngon(kCx - 3000, kCy - 3000, 700, 6)}}));
  const testing::CliResult updated =
      RunWrite(store_, "polygon update --update-tiles " + q_ + " " + id + " " + moved);
  EXPECT_NE(updated.out.find("tiles of 'terrain': "), std::string::npos) << updated.out;
  expect_tiles_with(last_tx().get<int64_t>());
  const std::string new_id = std::to_string(NewFeature(updated));

  auto opened = Store::Open(store_);
  ASSERT_TRUE(opened.ok()) << opened.status().ToString();
  ASSERT_TRUE((*opened)->db().Exec("UPDATE tile_pyramids SET extensions = 'bogus'").ok());
  opened->reset();
  ExpectRejected(store_, "polygon remove --update-tiles " + q_ + " " + new_id,
                 "updating the tiles of the edit: unknown tile extension 'bogus'");
  ExpectRejected(store_, "polygon update --update-tiles " + q_ + " " + new_id + " " + squares,
                 "updating the tiles of the edit");
}

}  // namespace
}  // namespace tinbase
