// `revert`, `history`, `changes --json` (the features of each transaction) and `export --as-of`
// end to end on the Hamersley data: the past is exported with the features it had (the GeoJSON
// read back by OGR's ogrinfo, a reader we did not write), and each bad input of issue 28 is one
// clear line with the store unchanged. A revert says whether the mesh came back exactly, reverts
// points edits, and with --update-tiles leaves nothing for `tiles update`.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "tests/support/cli_support.h"
#include "tests/support/gdal_tools.h"
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

class HistoryCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    testing::CopyRecipeStore(testing::HamersleyTerrainRecipe(10), store_);
    auto info = Json(RunCli("info --json " + Quote(store_)));
    const auto& b = info["dems"][0]["bbox"];
    cx_ = (b[0].get<double>() + b[2].get<double>()) / 2;
    cy_ = (b[1].get<double>() + b[3].get<double>()) / 2;
  }

  // A square of half-side `h` around (cx + dx, cy), as a GeoJSON file.
  std::string Square(const std::string& name, double dx, double h) {
    const std::string path = dir_.Path(name);
    const double x = cx_ + dx, y = cy_;
    std::ofstream(path) << R"({"type":"FeatureCollection","crs":{"type":"name","properties":)"
                        << R"({"name":"EPSG:28350"}},"features":[{"type":"Feature",)"
                        << R"("properties":{},"geometry":{"type":"Polygon","coordinates":[[)"
                        << "[" << x - h << "," << y - h << "],[" << x + h << "," << y - h << "],["
                        << x + h << "," << y + h << "],[" << x - h << "," << y + h << "],[" << x - h
                        << "," << y - h << "]]]}}]}";
    return path;
  }

  // The transaction of the last edit and the newest feature it touched, from `changes --json`.
  std::pair<int64_t, int64_t> LastEdit() {
    const nlohmann::json changes = Json(RunCli("changes --json " + Quote(store_)));
    const nlohmann::json& last = changes.back();
    return {last["tx"].get<int64_t>(),
            last["features"].empty() ? 0 : last["features"].back().get<int64_t>()};
  }

  TempDir dir_;
  std::string store_;
  double cx_ = 0, cy_ = 0;
};

TEST_F(HistoryCliTest, RevertHistoryChangesAndExportAsOf) {
  RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(Square("a.geojson", 0, 2000)) +
                       " --surface terrain --mode fill --tag a");
  const auto [tx_a, fa] = LastEdit();
  ASSERT_GT(fa, 0);
  const auto count = [&](const std::string& extra) {
    return Json(RunCli("export " + Quote(store_) + " --surface terrain -o " +
                       Quote(dir_.Path("count.obj")) + " --json" + extra))["triangles"]
        .get<int64_t>();
  };
  const int64_t all_at_a = count(""), visible_at_a = count(" --visible-only");
  RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(Square("b.geojson", 3000, 1500)) +
                       " --surface terrain --mode erase");
  const auto [tx_b, fb] = LastEdit();
  EXPECT_NE(fb, fa);

  // The past, exported: exactly the mesh after a (from the mesh images), every triangle and the
  // visible ones; OGR reads every triangle written; the store is unchanged.
  const auto visible = [&](const std::string& extra, const std::string& out) {
    return Json(RunCli("export " + Quote(store_) + " --surface terrain --visible-only -o " +
                       Quote(dir_.Path(out)) + " --json" + extra))["triangles"]
        .get<int64_t>();
  };
  const auto before = testing::TableChecksums(store_);
  const std::string past = dir_.Path("past.geojson");
  const int64_t visible_then = visible(" --as-of " + std::to_string(tx_a), "past.geojson");
  EXPECT_EQ(testing::TableChecksums(store_), before) << "export --as-of changed the store";
  EXPECT_EQ(visible_then, visible_at_a);
  const int64_t all_then =
      Json(RunCli("export " + Quote(store_) + " --surface terrain --as-of " + std::to_string(tx_a) +
                  " -o " + Quote(dir_.Path("all.obj")) + " --json"))["triangles"]
          .get<int64_t>();
  EXPECT_EQ(all_then, all_at_a);
  if (testing::HaveTool("ogrinfo")) {
    const testing::ToolResult info = testing::RunTool("ogrinfo -ro -so -al " + Quote(past));
    std::smatch m;
    ASSERT_TRUE(std::regex_search(info.out, m, std::regex("Feature Count: (\\d+)"))) << info.out;
    EXPECT_EQ(std::stoll(m[1]), visible_then);
  }

  // Update a, then revert the add: refused, naming the update; with --cascade both go.
  RunWrite(store_, "polygon update " + Quote(store_) + std::string(" ") + std::to_string(fa) + " " +
                       Quote(Square("a2.geojson", -500, 1200)));
  const auto [tx_c, fc] = LastEdit();
  ExpectRejected(
      store_, "revert " + Quote(store_) + std::string(" ") + std::to_string(tx_a),
      std::string("changed again by transaction ") + std::to_string(tx_c) + " (polygon update)");
  ExpectRejected(store_, "revert " + Quote(store_) + " 99999", "no transaction 99999");
  ExpectRejected(store_,
                 "export " + Quote(store_) + " --surface terrain --as-of 99999 -o " +
                     Quote(dir_.Path("future.obj")),
                 "in the future");
  const nlohmann::json changes = Json(RunCli("changes --json " + Quote(store_)));
  for (const nlohmann::json& c : changes) {
    if (c["action"] != "build") continue;
    ExpectRejected(
        store_,
        "revert " + Quote(store_) + std::string(" ") + std::to_string(c["tx"].get<int64_t>()),
        "is not an edit of features");
  }

  const nlohmann::json reverted = Json(RunWrite(
      store_, "revert " + Quote(store_) + std::string(" ") + std::to_string(tx_c) + " --json"));
  EXPECT_EQ(reverted["reverted"], nlohmann::json::array({tx_c}));
  EXPECT_EQ(reverted["restored_features"], nlohmann::json::array({fa}));
  EXPECT_EQ(reverted["removed_features"], nlohmann::json::array({fc}));
  EXPECT_EQ(reverted["exact"], true) << reverted.dump();

  const nlohmann::json history = Json(RunCli(
      "history " + Quote(store_) + std::string(" --feature ") + std::to_string(fa) + " --json"));
  ASSERT_EQ(history["versions"].size(), 3u) << history.dump();
  EXPECT_EQ(history["versions"][0]["state"], "added");
  EXPECT_EQ(history["versions"][1]["state"], "removed");
  EXPECT_EQ(history["versions"][1]["with"], nlohmann::json::array({fc}));
  EXPECT_EQ(history["versions"][2]["state"], "restored");
  EXPECT_EQ(history["versions"][2]["tag"], "a");
  ExpectRejected(store_, "history " + Quote(store_) + " --feature 99999", "has no history");

  RunWrite(store_,
           "revert " + Quote(store_) + std::string(" ") + std::to_string(tx_b) + " --cascade");
}

TEST_F(HistoryCliTest, RevertUpdatesTilesRevertsPointsAndSaysWhenNotExact) {
  RunWrite(store_, "tiles build " + Quote(store_) + " --surface terrain --max-zoom 9");
  RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(Square("a.geojson", 0, 1500)) +
                       " --surface terrain --mode replace --level 700");
  const auto [tx_a, fa] = LastEdit();
  RunWrite(store_, "tiles update " + Quote(store_) + " --surface terrain");
  const nlohmann::json reverted = Json(RunWrite(
      store_, "revert " + Quote(store_) + " " + std::to_string(tx_a) + " --update-tiles --json"));
  EXPECT_EQ(reverted["exact"], true) << reverted.dump();
  ASSERT_EQ(reverted["tiles"].size(), 1u) << reverted.dump();
  EXPECT_EQ(reverted["tiles"][0]["surface"], "terrain");
  EXPECT_GT(reverted["tiles"][0]["rewritten"].get<int64_t>(), 0) << reverted.dump();
  const nlohmann::json again =
      Json(RunCli("tiles update " + Quote(store_) + " --surface terrain --json"));
  EXPECT_EQ(again["changes"], 0) << "the revert's tiles committed with it";
  EXPECT_EQ(RunCli("check --full " + Quote(store_)).exit_code, 0);

  const std::string shots = dir_.Path("shots.xyz");
  std::ofstream(shots) << cx_ + 37.5 << " " << cy_ + 12.25 << " 650.5\n"
                       << cx_ - 410.75 << " " << cy_ + 233.5 << " 640.25\n";
  RunWrite(store_, "points add " + Quote(store_) + " " + Quote(shots) + " --surface terrain");
  const auto [tx_p, fp] = LastEdit();
  ASSERT_GT(fp, 0);
  const nlohmann::json points =
      Json(RunWrite(store_, "revert " + Quote(store_) + " " + std::to_string(tx_p) + " --json"));
  EXPECT_EQ(points["removed_features"], nlohmann::json::array({fp}));
  EXPECT_EQ(points["exact"], true) << points.dump();

  // b over a's region: a's rows are b's now, so a's revert re-refines and says why.
  RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(Square("c.geojson", 0, 1500)) +
                       " --surface terrain --mode fill --tag c");
  const auto [tx_c, fc] = LastEdit();
  RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(Square("d.geojson", 800, 1200)) +
                       " --surface terrain --mode erase");
  const nlohmann::json fallback =
      Json(RunWrite(store_, "revert " + Quote(store_) + " " + std::to_string(tx_c) + " --json"));
  EXPECT_EQ(fallback["exact"], false) << fallback.dump();
  EXPECT_NE(fallback["not_exact"].get<std::string>().find("changed since by another edit"),
            std::string::npos)
      << fallback.dump();
  const CliResult text = RunCli("check --full " + Quote(store_));
  EXPECT_EQ(text.exit_code, 0) << text.out << text.err;
}

}  // namespace
}  // namespace tinbase
