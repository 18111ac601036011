// The progress callbacks of the long library calls (DemImportOptions, SurfaceBuildOptions,
// PointImportOptions, PolygonAddOptions::progress): each reports fractions in [0, 1] that never
// go back and end at (or, where the count is an estimate, near) 1, and the result is the same as
// without a callback.
#include <gtest/gtest.h>

#include <mutex>
#include <vector>

#include "db/dem_store.h"
#include "db/integrity_check.h"
#include "db/point_import.h"
#include "db/polygon_editor.h"
#include "db/surface_builder.h"
#include "db/surface_store.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::TempDir;

// Collects the fractions a callback receives (a points import may report from its triangulating
// task, so under a lock).
class Fractions {
 public:
  std::function<void(double)> Callback() {
    return [this](double f) {
      const std::lock_guard<std::mutex> lock(mutex_);
      seen_.push_back(f);
    };
  }
  // Each in [0, 1], never less than the one before, the last at least `last`.
  void ExpectRising(double last) const {
    ASSERT_FALSE(seen_.empty());
    for (size_t i = 0; i < seen_.size(); ++i) {
      EXPECT_GE(seen_[i], 0.0);
      EXPECT_LE(seen_[i], 1.0);
      if (i > 0) {
        EXPECT_GE(seen_[i], seen_[i - 1]) << "at call " << i;
      }
    }
    EXPECT_GE(seen_.back(), last);
  }
  size_t size() const { return seen_.size(); }

 private:
  std::mutex mutex_;
  std::vector<double> seen_;
};

void ExpectStoreIntact(Store& store) {
  auto problems = CheckStore(store);
  ASSERT_TRUE(problems.ok()) << problems.status().ToString();
  for (const Problem& p : *problems) ADD_FAILURE() << p.code << ": " << p.message;
}

// The Hamersley DEM imported (with `progress`) and a greedy surface built at 5 m.
std::unique_ptr<Store> HamersleyStore(const TempDir& dir, const std::string& name,
                                      Fractions* import, Fractions* build) {
  auto store = Store::Create(dir.Path(name), "");
  EXPECT_TRUE(store.ok()) << store.status().ToString();
  if (!store.ok()) return nullptr;
  DemImportOptions o;
  o.block_size = 64;  // several blocks and overview levels
  if (import) o.progress = import->Callback();
  auto imported = DemStore(**store).Import({DataPath("geology/hamersley/dtm_rp.tif")}, o);
  EXPECT_TRUE(imported.ok()) << imported.status().ToString();
  SurfaceBuildOptions b;
  b.surface = "terrain";
  b.greedy.tolerance = 5;
  if (build) b.progress = build->Callback();
  auto built = BuildSurfaceFromDem(**store, b);
  EXPECT_TRUE(built.ok()) << built.status().ToString();
  return std::move(*store);
}

TEST(ProgressCallbacks, DemImportAndTinBuildReportRisingFractionsAndBuildTheSame) {
  TempDir dir;
  Fractions import, build;
  auto with = HamersleyStore(dir, "with.tinbase", &import, &build);
  auto without = HamersleyStore(dir, "without.tinbase", nullptr, nullptr);
  ASSERT_TRUE(with && without);
  import.ExpectRising(1.0);
  EXPECT_GT(import.size(), 4u);  // block by block, not only at the end
  build.ExpectRising(1.0);
  SurfaceStore a(*with), b(*without);
  auto la = a.Load(*a.Find("terrain"));
  auto lb = b.Load(*b.Find("terrain"));
  ASSERT_TRUE(la.ok() && lb.ok());
  EXPECT_EQ(la->tin.vertices.size(), lb->tin.vertices.size());
  EXPECT_EQ(la->tin.triangles.size(), lb->tin.triangles.size());
  ExpectStoreIntact(*with);
}

TEST(ProgressCallbacks, PolygonAddReportsFeatureByFeature) {
  for (bool each : {true, false}) {
    TempDir dir;
    auto store = HamersleyStore(dir, "s.tinbase", nullptr, nullptr);
    ASSERT_TRUE(store);
    Fractions seen;
    PolygonAddOptions o;
    o.surface = "terrain";
    o.file = DataPath("geology/hamersley/geology.geojson");
    o.mode = FeatureMode::kFill;
    o.tag_field = "unitname";
    o.each = each;
    o.progress = seen.Callback();
    auto report = AddPolygons(*store, o);
    ASSERT_TRUE(report.ok()) << report.status().ToString();
    EXPECT_EQ(report->features, 61);
    // The last call comes before the last feature (with `each`) or the one edit; the CLI's bar
    // draws 100 % when the call returns.
    EXPECT_GE(seen.size(), 61u) << "each " << each;
    seen.ExpectRising(each ? 60.0 / 61 : 0.5);
    ExpectStoreIntact(*store);
  }
}

TEST(ProgressCallbacks, PointsImportReportsReadingThenTriangles) {
  TempDir dir;
  auto store = Store::Create(testing::StoreTarget(dir, "p.tinbase"), "");
  ASSERT_TRUE(store.ok());
  Fractions seen;
  PointImportOptions o;
  o.file = DataPath("las/autzen_trim.las");
  o.surface = "ground";
  o.progress = seen.Callback();
  auto report = ImportPoints(**store, o);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->points.kept, 26107);
  EXPECT_GE(seen.size(), 3u);  // start, points read, the triangles
  // Triangles against 2 a point: a triangulation has a few fewer (2n - 2 - hull vertices).
  seen.ExpectRising(0.99);
  ExpectStoreIntact(**store);
}

}  // namespace
}  // namespace tinbase
