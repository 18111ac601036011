// `tinbase points import` end to end on the PDAL test LAS files: a checked Delaunay surface,
// thinning keeps fewer points, LAZ and broken files are refused and change nothing.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/support/cli_support.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::Quote;
using testing::RunCli;
using testing::StoreTarget;
using testing::TableChecksums;
using testing::TempDir;

nlohmann::json SurfaceNamed(const std::string& store, const std::string& name) {
  auto r = RunCli("info --json " + Quote(store));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json info = nlohmann::json::parse(r.out);
  for (const auto& s : info["surfaces"])
    if (s["name"] == name) return s;
  ADD_FAILURE() << "no surface " << name;
  return {};
}

TEST(PointsCli, LasBecomesACheckedSurfaceAndThinningKeepsFewerPoints) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "p.tinbase");
  ASSERT_EQ(RunCli("init " + Quote(store)).exit_code, 0);
  const std::string las = Quote(DataPath("las/autzen_trim.las"));
  auto full = RunCli("points import " + Quote(store) + " " + las + " --surface full");
  ASSERT_EQ(full.exit_code, 0) << full.err;
  auto thin = RunCli("points import " + Quote(store) + " " + las + " --surface thin --thin");
  ASSERT_EQ(thin.exit_code, 0) << thin.err;
  EXPECT_EQ(RunCli("check " + Quote(store)).exit_code, 0);
  const auto a = SurfaceNamed(store, "full");
  const auto b = SurfaceNamed(store, "thin");
  EXPECT_EQ(a["vertices"], 26107);  // Autzen's ground-classified points
  EXPECT_LT(b["vertices"].get<int>(), a["vertices"].get<int>());
  EXPECT_GT(b["vertices"].get<int>(), a["vertices"].get<int>() / 2);
  EXPECT_EQ(a["kind"], "delaunay");
}

TEST(PointsCli, DensityWindowThinsAndBadWindowsAreRefusedUnchanged) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "p.tinbase");
  ASSERT_EQ(RunCli("init " + Quote(store)).exit_code, 0);
  const std::string las = Quote(DataPath("las/autzen_trim.las"));
  auto thin = RunCli("points import " + Quote(store) + " " + las +
                     " --surface window --thin --density 10/150");
  ASSERT_EQ(thin.exit_code, 0) << thin.err;
  EXPECT_EQ(RunCli("check " + Quote(store)).exit_code, 0);
  const int kept = SurfaceNamed(store, "window")["vertices"].get<int>();
  EXPECT_LT(kept, 26107);
  EXPECT_GT(kept, 26107 / 2);

  const auto before = TableChecksums(store);
  for (const auto& [density, expected] :
       {std::pair{"10", "no '/'"}, std::pair{"ten/150", "not a number"},
        std::pair{"10/0", "the area must be positive"}, std::pair{"10/15x", "area is not"},
        std::pair{"-1/150", "the count must be >= 0"}}) {
    auto r = RunCli("points import " + Quote(store) + " " + las +
                    " --surface bad --thin --density " + density);
    EXPECT_NE(r.exit_code, 0) << density;
    EXPECT_NE(r.err.find(std::string("--density '") + density + "'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  }
  auto both = RunCli("points import " + Quote(store) + " " + las +
                     " --surface bad --thin --density 10/150 --max-cell-area 15");
  EXPECT_NE(both.exit_code, 0);
  EXPECT_NE(both.err.find("give one"), std::string::npos) << both.err;
  EXPECT_EQ(TableChecksums(store), before);
}

TEST(PointsCli, LazAndBrokenFilesAreRefusedUnchanged) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "p.tinbase");
  ASSERT_EQ(RunCli("init " + Quote(store)).exit_code, 0);
  // A LAS header whose point format has the compression bit set, as LAZ writers mark it.
  std::ifstream in(DataPath("las/mvk-thin.las"), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string laz = bytes;
  laz[104] = static_cast<char>(laz[104] | 0x80);
  const std::string laz_path = dir.Path("x.laz");
  std::ofstream(laz_path, std::ios::binary) << laz;
  const std::string truncated = dir.Path("short.las");
  std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  const auto before = TableChecksums(store);
  for (const auto& [file, expected] :
       {std::pair{laz_path, std::string("LAZ")}, std::pair{truncated, std::string("short.las")}}) {
    auto r = RunCli("points import " + Quote(store) + " " + Quote(file) + " --surface s");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  }
  EXPECT_EQ(TableChecksums(store), before);
}

}  // namespace
}  // namespace tinbase
