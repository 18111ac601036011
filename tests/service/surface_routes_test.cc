// The surface read routes through a real socket: what a client learns of the store's surfaces.
#include <gtest/gtest.h>

#include "tests/support/service_support.h"

namespace tinbase::testing {
namespace {

class SurfaceRoutesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = dir_.Path("s.tinbase");
    CopyDemoStore(store_);
    service::ServiceOptions options;
    options.store_path = store_;
    service_ = std::make_unique<TestService>(options);
    ASSERT_TRUE(service_->running());
  }
  TempDir dir_;
  std::string store_;
  std::unique_ptr<TestService> service_;
};

TEST_F(SurfaceRoutesTest, ListsTheSurfacesWithTheCountsInfoPrints) {
  const nlohmann::json info = Json(RunCli("info --json " + Quote(store_)));
  const nlohmann::json answer = JsonAnswer(service_->Client()->Get("/surfaces"));
  ASSERT_EQ(answer["surfaces"].size(), 1u);
  const nlohmann::json& s = answer["surfaces"][0];
  EXPECT_EQ(s["name"], "t");
  EXPECT_EQ(s["triangles"], info["surfaces"][0]["triangles"]);
  EXPECT_EQ(s["vertices"], info["surfaces"][0]["vertices"]);
  EXPECT_EQ(s["tolerance"], 20.0);
  EXPECT_EQ(s["crs"], info["crs"]);
  // The surface covers the DEM it was built on, to within one cell.
  ASSERT_EQ(s["extent"].size(), 6u);
  const nlohmann::json& dem = info["dems"][0];
  const double cell = dem["cell_size"][0].get<double>();
  for (int i : {0, 1}) {
    EXPECT_NEAR(s["extent"][i].get<double>(), dem["bbox"][i].get<double>(), cell);          // min
    EXPECT_NEAR(s["extent"][3 + i].get<double>(), dem["bbox"][2 + i].get<double>(), cell);  // max
  }
  EXPECT_LT(s["extent"][2].get<double>(), s["extent"][5].get<double>());
}

TEST_F(SurfaceRoutesTest, OneSurfaceByName) {
  const nlohmann::json s = JsonAnswer(service_->Client()->Get("/surfaces/t"));
  EXPECT_EQ(s["name"], "t");
  EXPECT_GT(s["triangles"].get<int64_t>(), 1000);
}

TEST_F(SurfaceRoutesTest, AnUnknownSurfaceOrPathIsAJson404) {
  ExpectJsonError(service_->Client()->Get("/surfaces/nope"), 404, "no surface named 'nope'");
  ExpectJsonError(service_->Client()->Get("/no/such/route"), 404, "no route for GET");
}

}  // namespace
}  // namespace tinbase::testing
