// CutFill on a store: two plane surfaces triangulated differently, over their overlap and inside
// a polygon file (exact answers), and each bad request: surfaces that do not overlap (at all, or
// inside the polygon), an unknown surface, feature or file, a feature and a file at once.
#include "db/query/cut_fill.h"

#include <gtest/gtest.h>

#include "db/query/measure_source.h"
#include "tests/core/measure/analytic_tins.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::GridTin;
using testing::TempDir;

constexpr double kX = 600000, kY = 5100000;

CutFillRequest Request(const std::string& base, const std::string& top, int64_t feature = 0,
                       const std::string& file = "") {
  CutFillRequest r;
  r.base = base, r.top = top, r.feature = feature, r.polygon_file = file;
  return r;
}

class CutFillTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = Store::Create(testing::StoreTarget(dir_, "s.tinbase"), "EPSG:32632");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    // Ground z = 100 over [0, 200]^2; design z = 100 + (x - 150) / 10 over [100, 300] x [0, 200];
    // far away z = 0 over [1000, 1100]^2 (offsets from kX, kY).
    Add("ground", GridTin(8, 8, kX, kY, kX + 200, kY + 200, [](double, double) { return 100; }));
    Add("design", GridTin(5, 7, kX + 100, kY, kX + 300, kY + 200,
                          [](double x, double) { return 100 + (x - kX - 150) / 10; }));
    Add("far", GridTin(2, 2, kX + 1000, kY + 1000, kX + 1100, kY + 1100,
                       [](double, double) { return 0; }));
    testing::ExpectStoreIntact(*store_);
  }

  void Add(const std::string& name, const Tin& tin) {
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    SurfaceInfo spec;
    spec.name = name;
    spec.kind = SurfaceKind::kFree;
    spec.method = "test";
    ASSERT_TRUE(SurfaceStore(*store_).Create(spec, tin).ok());
    ASSERT_TRUE((*tx)->Commit().ok());
  }

  std::string Square(double x0, double y0, double x1, double y1) {
    return testing::WritePolygons(dir_, "square.geojson",
                                  {{{{kX + x0, kY + y0},
                                     {kX + x1, kY + y0},
                                     {kX + x1, kY + y1},
                                     {kX + x0, kY + y1},
                                     {kX + x0, kY + y0}}}},
                                  32632);
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
};

// Over the overlap [100, 200] x [0, 200] the design is 5 m below the ground at x = 100 and 5 m
// above at x = 200, crossing at 150: cut and fill are wedges of 5 / 2 * 50 * 200 = 25000 m3.
TEST_F(CutFillTest, PlanesOverTheirOverlapAreExact) {
  auto r = CutFill(*store_, Request("ground", "design"));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_FALSE(r->inside_polygon);
  EXPECT_NEAR(r->volume.plan_area, 20000, 1e-6);
  EXPECT_NEAR(r->volume.split.below_volume, 25000, 1e-6);  // cut
  EXPECT_NEAR(r->volume.split.above_volume, 25000, 1e-6);  // fill
  EXPECT_NEAR(r->volume.split.above_area, 10000, 1e-6);
}

// Inside [160, 190] x [50, 150] only fill: the mean rise (0.1 * 25 = 2.5 m) over 3000 m2.
TEST_F(CutFillTest, InsideAPolygonFileIsExact) {
  auto r = CutFill(*store_, Request("ground", "design", 0, Square(160, 50, 190, 150)));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_TRUE(r->inside_polygon);
  EXPECT_NEAR(r->volume.plan_area, 3000, 1e-6);
  EXPECT_NEAR(r->volume.split.above_volume, 7500, 1e-6);
  EXPECT_EQ(r->volume.split.below_volume, 0);
}

TEST_F(CutFillTest, SurfacesThatDoNotOverlapAreNamed) {
  auto r = CutFill(*store_, Request("ground", "far"));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(r.status().message(), "surfaces 'ground' and 'far' do not overlap");
  r = CutFill(*store_, Request("ground", "design", 0, Square(10, 10, 50, 50)));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().message(),
            "surfaces 'ground' and 'design' do not overlap inside the polygon");
}

TEST_F(CutFillTest, BadRequestsAreRejected) {
  auto r = CutFill(*store_, Request("ground", "nope"));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kNotFound);
  EXPECT_NE(r.status().message().find("nope"), std::string::npos);
  r = CutFill(*store_, Request("ground", "design", 99));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().message(), "no feature 99 on surface 'ground' or 'design'");
  r = CutFill(*store_, Request("ground", "design", 1, Square(0, 0, 1, 1)));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  r = CutFill(*store_, Request("ground", "design", 0, dir_.Path("missing.geojson")));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("missing.geojson"), std::string::npos);
}

TEST_F(CutFillTest, MeasureSourceHasTheStoreFrame) {
  auto source = LoadMeasureSource(*store_, "design", {});
  ASSERT_TRUE(source.ok()) << source.status().ToString();
  EXPECT_FALSE(source->frame.geographic());
  ASSERT_TRUE(source->crs.has_value());
  EXPECT_EQ(source->crs->Epsg(), 32632);
  EXPECT_EQ(source->part.tin.triangles.size(), 70u);
}

}  // namespace
}  // namespace tinbase
