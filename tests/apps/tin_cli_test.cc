// `tinbase tin build --method collapse` and `tinbase dem from-contours` end to end on real data:
// each write followed by `check`, and bad input rejected with one line on stderr, a non-zero exit
// and the store left exactly as it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "tests/support/cli_support.h"
#include "tests/support/make_contours.h"
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
using testing::TableChecksums;
using testing::TempDir;

nlohmann::json Surface(const std::string& store, const std::string& name) {
  CliResult r = RunCli("info --json " + Quote(store));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json info = nlohmann::json::parse(r.out);
  for (const auto& s : info["surfaces"]) {
    if (s["name"] == name) return s;
  }
  ADD_FAILURE() << "no surface " << name;
  return {};
}

class TinCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    testing::CopyRecipeStore(testing::HamersleyDemRecipe(), store_);
  }
  TempDir dir_;
  std::string store_;
};

TEST_F(TinCliTest, CollapseBuildsFreeSurfacesWithinTheBudget) {
  for (const auto& [name, faces, strategy] :
       {std::tuple{"q6000", 6000, "quadric"}, {"q60", 60, "quadric"}, {"p600", 600, "paper"}}) {
    CliResult r = RunWrite(store_, "tin build " + Quote(store_) + " --surface " + name +
                                       " --method collapse --faces " + std::to_string(faces) +
                                       " --strategy " + strategy);
    EXPECT_NE(r.out.find("(collapse)"), std::string::npos) << r.out;
    const auto s = Surface(store_, name);
    EXPECT_EQ(s["kind"], "free");
    EXPECT_EQ(s["method"], "collapse");
    EXPECT_LE(s["triangles"].get<int>(), faces);
    EXPECT_GT(s["triangles"].get<int>(), faces / 2);
  }
}

// Every tolerance-driven method: the surface kind says whether it is Delaunay, and the stored
// tolerance is what the surface keeps (VIP has no bound: its measured error).
TEST_F(TinCliTest, GreedyRtinAndVipBuildCheckedSurfaces) {
  RunWrite(store_, "tin build " + Quote(store_) + " --surface g --method greedy --tolerance 15");
  RunWrite(store_, "tin build " + Quote(store_) + " --surface r --method rtin --tolerance 15");
  RunWrite(store_, "tin build " + Quote(store_) + " --surface v --method vip --threshold 30");
  EXPECT_EQ(Surface(store_, "g")["kind"], "delaunay");
  EXPECT_EQ(Surface(store_, "r")["kind"], "free");
  EXPECT_EQ(Surface(store_, "v")["kind"], "delaunay");
  EXPECT_NEAR(Surface(store_, "g")["tolerance"].get<double>(), 15, 1e-6);  // measured, may round up
  EXPECT_NEAR(Surface(store_, "r")["tolerance"].get<double>(), 15, 1e-6);
  EXPECT_GT(Surface(store_, "v")["tolerance"].get<double>(), 0);
  const auto before = TableChecksums(store_);
  CliResult r = RunCli("tin build " + Quote(store_) +
                       " --surface x --method rtin --tolerance 5 "
                       "--max-points 100");
  EXPECT_NE(r.exit_code, 0);
  r = RunCli("tin build " + Quote(store_) + " --surface x --method nosuch");
  EXPECT_NE(r.err.find("nosuch"), std::string::npos) << r.err;
  EXPECT_EQ(TableChecksums(store_), before);
}

TEST_F(TinCliTest, CollapseRejectsBadOptions) {
  const std::string build = "tin build " + Quote(store_) + " --surface t --method collapse";
  ExpectRejected(store_, build, "face budget");
  ExpectRejected(store_, build + " --faces 1", "face budget");
  ExpectRejected(store_, build + " --faces 100 --strategy fastest",
                 "unknown collapse strategy 'fastest'");
  ExpectRejected(store_, "tin build " + Quote(store_) + " --surface t --method magic",
                 "unknown TIN method 'magic'");
}

// An option the chosen method would ignore is refused, naming the option and the methods it is for.
TEST_F(TinCliTest, OptionsOfAnotherMethodAreRejected) {
  const std::string build = "tin build " + Quote(store_) + " --surface t";
  ExpectRejected(store_, build + " --faces 500", "--faces applies only to --method collapse");
  ExpectRejected(store_, build + " --method rtin --tolerance 5 --strategy paper",
                 "--strategy applies only to --method collapse");
  ExpectRejected(store_, build + " --method greedy --threshold 3",
                 "--threshold applies only to --method vip, not greedy");
  ExpectRejected(store_, build + " --method vip --tolerance 3",
                 "--tolerance applies only to --method greedy or rtin, not vip");
  ExpectRejected(store_, build + " --method collapse --faces 500 --max-points 40",
                 "--max-points applies only to --method greedy or vip");
}

TEST_F(TinCliTest, DemFromContoursThenCollapse) {
  const std::string contours = dir_.Path("contours.gpkg");
  ASSERT_TRUE(testing::MakeContours(DataPath("geology/hamersley/dtm_rp.tif"), contours, 25).ok());
  CliResult r = RunWrite(store_, "dem from-contours " + Quote(store_) + " " + Quote(contours) +
                                     " --field ELEV --cell 344.404386931320971 --name fromc");
  EXPECT_NE(r.out.find("DEM 'fromc'"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" 0 left"), std::string::npos) << r.out;
  CliResult info = RunCli("info --json " + Quote(store_));
  ASSERT_EQ(info.exit_code, 0);
  const auto dems = nlohmann::json::parse(info.out)["dems"];
  ASSERT_EQ(dems.size(), 2u);
  RunWrite(store_, "tin build " + Quote(store_) +
                       " --surface c --dem fromc --method collapse --faces 3000");
  EXPECT_LE(Surface(store_, "c")["triangles"].get<int>(), 3000);

  ExpectRejected(store_,
                 "dem from-contours " + Quote(store_) + " " + Quote(contours) +
                     " --field HEIGHT --cell 300 --name other",
                 "no field 'HEIGHT'");
  ExpectRejected(store_,
                 "dem from-contours " + Quote(store_) + " " + Quote(contours) +
                     " --field ELEV --cell 300 --name fromc",
                 "already exists");
  ExpectRejected(store_,
                 "dem from-contours " + Quote(store_) + " " + Quote(dir_.Path("none.shp")) +
                     " --field ELEV --cell 300 --name other",
                 "none.shp");
}

}  // namespace
}  // namespace tinbase
