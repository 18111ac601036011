// `revert`, `history` and `export --as-of` on a PostgreSQL store (the throwaway server of
// scripts/pg-server.sh; tests/support/postgres_support.h): the versions, the id kept by a
// restored feature, the conflict and the cascade behave as on SQLite, the reverts give the exact
// mesh back (an OBJ export byte for byte), and the store passes the full check after each write.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/support/cli_support.h"
#include "tests/support/postgres_support.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::Json;
using testing::Quote;
using testing::RunCli;
using testing::RunWrite;
using testing::TempDir;

// A square of half-side `h` around (x, y) in EPSG:28350, as a GeoJSON file.
std::string Square(const TempDir& dir, const std::string& name, double x, double y, double h) {
  const std::string path = dir.Path(name);
  std::ofstream(path) << R"({"type":"FeatureCollection","crs":{"type":"name","properties":)"
                      << R"({"name":"EPSG:28350"}},"features":[{"type":"Feature",)"
                      << R"("properties":{},"geometry":{"type":"Polygon","coordinates":[[)"
                      << "[" << x - h << "," << y - h << "],[" << x + h << "," << y - h << "],["
                      << x + h << "," << y + h << "],[" << x - h << "," << y + h << "],[" << x - h
                      << "," << y - h << "]]]}}]}";
  return path;
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(HistoryPostgresCliTest, RevertHistoryAndAsOfOnPostgres) {
  const std::string store = testing::FreshPostgresStore("history");
  ASSERT_FALSE(store.empty());
  TempDir dir;
  RunWrite(store, "init " + Quote(store));
  RunWrite(store,
           "dem import " + Quote(store) + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
  RunWrite(store, "tin build " + Quote(store) + " --surface terrain --tolerance 10");
  constexpr double kCx = 539300, kCy = 7497340;
  const auto export_obj = [&](const std::string& name) {
    RunCli("export " + Quote(store) + " --surface terrain -o " + Quote(dir.Path(name)));
    return ReadFile(dir.Path(name));
  };
  const std::string original = export_obj("original.obj");
  ASSERT_FALSE(original.empty());
  RunWrite(store, "polygon add " + Quote(store) + " " +
                      Quote(Square(dir, "a.geojson", kCx, kCy, 2000)) +
                      " --surface terrain --mode fill --tag a");
  nlohmann::json changes = Json(RunCli("changes --json " + Quote(store)));
  const int64_t tx_a = changes.back()["tx"].get<int64_t>();
  const int64_t fa = changes.back()["features"][0].get<int64_t>();
  RunWrite(store, "polygon update " + Quote(store) + " " + std::to_string(fa) + " " +
                      Quote(Square(dir, "b.geojson", kCx, kCy, 1200)));
  changes = Json(RunCli("changes --json " + Quote(store)));
  const int64_t tx_b = changes.back()["tx"].get<int64_t>();
  ASSERT_EQ(changes.back()["features"].size(), 2u);

  testing::CliResult conflict = RunCli("revert " + Quote(store) + " " + std::to_string(tx_a));
  EXPECT_NE(conflict.exit_code, 0);
  EXPECT_NE(conflict.err.find("changed again by transaction " + std::to_string(tx_b)),
            std::string::npos)
      << conflict.err;
  const nlohmann::json past =
      Json(RunCli("export " + Quote(store) + " --surface terrain --tag a --as-of " +
                  std::to_string(tx_a) + " -o " + Quote(dir.Path("past.obj")) + " --json"));
  EXPECT_GT(past["triangles"].get<int64_t>(), 0);

  const nlohmann::json reverted =
      Json(RunWrite(store, "revert " + Quote(store) + " " + std::to_string(tx_b) + " --json"));
  EXPECT_EQ(reverted["restored_features"], nlohmann::json::array({fa}));
  EXPECT_EQ(reverted["exact"], true) << reverted.dump();
  const nlohmann::json history =
      Json(RunCli("history " + Quote(store) + " --feature " + std::to_string(fa) + " --json"));
  ASSERT_EQ(history["versions"].size(), 3u) << history.dump();
  EXPECT_EQ(history["versions"][2]["state"], "restored");
  const nlohmann::json last =
      Json(RunWrite(store, "revert " + Quote(store) + " " + std::to_string(tx_a) + " --json"));
  EXPECT_EQ(last["exact"], true) << last.dump();
  EXPECT_TRUE(export_obj("back.obj") == original) << "the mesh is not the one built";
  const nlohmann::json info = Json(RunCli("info --json " + Quote(store)));
  EXPECT_EQ(info["surfaces"][0]["features"], 0) << "reverting the add took the feature out";
}

}  // namespace
}  // namespace tinbase
