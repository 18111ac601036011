// `polygon add` with polygons that overhang the surface's data area, end to end: the Luxembourg
// cantons over the country's DEM (nodata outside the border) are cut and reported on stderr and
// in --json; --strict refuses them as before; a polygon wholly off the DEM is skipped with a
// warning under --each and an error otherwise, the store then unchanged.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/cli_support.h"
#include "tests/support/store_target.h"
#include "tests/support/store_template.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::CliResult;
using testing::DataPath;
using testing::ExpectRejected;
using testing::Quote;
using testing::RunCli;
using testing::RunWrite;
using testing::StoreTarget;
using testing::TempDir;

class OverhangCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    static const testing::StoreRecipe recipe{
        "overhang_cli_test", [](const std::string& store, const TempDir&) {
          testing::MakeDemStore(store, "dem/elev.tif");
          RunWrite(store, "tin build " + Quote(store) + " --surface t --tolerance 5");
        }};
    testing::CopyRecipeStore(recipe, store_);
  }

  // Two squares in EPSG:4326: one in Luxembourg, one in the Atlantic, far off the DEM.
  std::string TwoSquares() {
    const std::string path = dir_.Path("two.geojson");
    std::ofstream(path) << R"({"type": "FeatureCollection", "features": [)"
                        << R"({"type": "Feature", "properties": {}, "geometry": {"type": )"
                        << R"("Polygon", "coordinates": [[[6.0, 49.6], [6.1, 49.6], [6.1, 49.7],)"
                        << R"( [6.0, 49.7], [6.0, 49.6]]]}},)"
                        << R"({"type": "Feature", "properties": {}, "geometry": {"type": )"
                        << R"("Polygon", "coordinates": [[[-30, 40], [-29, 40], [-29, 41],)"
                        << R"( [-30, 41], [-30, 40]]]}}]})";
    return path;
  }

  TempDir dir_;
  std::string store_;
};

TEST_F(OverhangCliTest, CantonsAreClippedAndReported) {
  const CliResult r = RunWrite(store_, "polygon add " + Quote(store_) + " " +
                                           Quote(DataPath("vector/lux/lux.shp")) +
                                           " --surface t --mode fill --tag-field NAME_2 --json");
  const nlohmann::json report = nlohmann::json::parse(r.out);
  EXPECT_EQ(report["features"].size(), 12u);
  ASSERT_TRUE(report["clipped"].is_array());
  ASSERT_FALSE(report["clipped"].empty());
  for (const nlohmann::json& cut : report["clipped"]) {
    EXPECT_GT(cut["feature"].get<int64_t>(), 0);
    EXPECT_NE(cut["label"].get<std::string>().find("lux.shp feature "), std::string::npos);
    EXPECT_GT(cut["area_outside"].get<double>(), 0);
  }
  EXPECT_NE(r.err.find("tinbase: clipped to the surface's data area: lux.shp feature "),
            std::string::npos)
      << r.err;
}

TEST_F(OverhangCliTest, StrictRefusesTheCantons) {
  ExpectRejected(store_,
                 "polygon add " + Quote(store_) + " " + Quote(DataPath("vector/lux/lux.shp")) +
                     " --surface t --mode fill --tag-field NAME_2 --strict",
                 "no elevation");
}

TEST_F(OverhangCliTest, WhollyOutsideIsAnErrorWithoutEach) {
  ExpectRejected(store_,
                 "polygon add " + Quote(store_) + " " + Quote(TwoSquares()) +
                     " --surface t --mode fill --tag x",
                 "two.geojson feature 1: lies wholly outside the data area of surface 't'");
}

TEST_F(OverhangCliTest, WhollyOutsideIsSkippedUnderEach) {
  const CliResult r = RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(TwoSquares()) +
                                           " --surface t --mode fill --tag x --each --json");
  const nlohmann::json report = nlohmann::json::parse(r.out);
  EXPECT_EQ(report["features"].size(), 1u);
  ASSERT_EQ(report["skipped"].size(), 1u);
  EXPECT_NE(report["skipped"][0].get<std::string>().find("two.geojson feature 1: lies wholly"),
            std::string::npos);
  EXPECT_TRUE(report["failures"].empty());
  EXPECT_NE(r.err.find("tinbase: skipped: two.geojson feature 1"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace tinbase
