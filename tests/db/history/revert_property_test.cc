// Issue 28's property: a random sequence of edits (add, update, remove of polygons in every
// painting mode) followed by the revert of each, in reverse order, returns a surface the full
// check passes after every revert, with exactly the original features (ids and rows). The mesh is
// not compared: a revert re-refines the regions it touches (tests/db/history/surface_signature.h).
// RapidCheck prints the seed of a failure.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "db/dem_store.h"
#include "db/history/revert.h"
#include "db/integrity_check.h"
#include "db/polygon_editor.h"
#include "db/surface_builder.h"
#include "tests/db/history/surface_signature.h"
#include "tests/support/polygon_files.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::PointList;
using testing::TempDir;

// RapidCheck reads RC_PARAMS on first use; a user's setting wins.
const bool kDefaultParams = [] {
  setenv("RC_PARAMS", "max_success=10", /*overwrite=*/0);
  return true;
}();

constexpr double kCx = 539300, kCy = 7497340, kCell = 344.404386931320971;

// The Hamersley store with its greedy surface, built once and copied for each case.
const std::string& BaseStore() {
  static TempDir dir;
  static const std::string path = [] {
    const std::string p = dir.Path("base.tinbase");
    auto store = Store::Create(p, "");
    EXPECT_TRUE(store.ok());
    DemStore dems(**store);
    EXPECT_TRUE(dems.Import({testing::DataPath("geology/hamersley/dtm_rp.tif")}, {}).ok());
    SurfaceBuildOptions o;
    o.surface = "terrain";
    o.greedy.tolerance = 5;
    EXPECT_TRUE(BuildSurfaceFromDem(**store, o).ok());
    return p;
  }();
  return path;
}

// A star-shaped (so simple) ring around a random point near the DEM's centre.
PointList RandomRing() {
  const double x = kCx + *rc::gen::inRange(-12, 13) * kCell * 0.77;
  const double y = kCy + *rc::gen::inRange(-12, 13) * kCell * 0.77;
  const double radius = *rc::gen::inRange(2, 11) * kCell;
  const int n = *rc::gen::inRange(4, 25);
  const double phase = *rc::gen::inRange(0, 628) / 100.0;
  PointList ring;
  for (int k = 0; k < n; ++k) {
    const double r = radius * *rc::gen::inRange(60, 101) / 100.0;
    const double a = phase + 2 * M_PI * k / n;
    ring.push_back({x + r * std::cos(a), y + r * std::sin(a)});
  }
  ring.push_back(ring.front());
  return ring;
}

FeatureMode RandomMode() {
  switch (*rc::gen::inRange(0, 7)) {
    case 0:
      return FeatureMode::kErase;
    case 1:
      return FeatureMode::kClip;
    case 2:
      return FeatureMode::kReplace;
    default:
      return FeatureMode::kFill;
  }
}

void AssertIntact(Store& store, const std::string& after) {
  auto problems = CheckStore(store, {.surface = {}, .full = true});
  RC_ASSERT(problems.ok());
  if (!problems->empty())
    RC_FAIL(after + std::string(": ") + std::to_string(problems->size()) + " problems, first " +
            problems->front().code + ": " + problems->front().message);
}

RC_GTEST_PROP(RevertProperty, EditsThenRevertsInReverseOrderGiveTheOriginalBack, ()) {
  TempDir dir;
  const std::string path = dir.Path("p.tinbase");
  std::filesystem::copy_file(BaseStore(), path);
  auto opened = Store::Open(path);
  RC_ASSERT(opened.ok());
  Store& store = **opened;
  const testing::SurfaceSignature original = testing::SignatureOf(store);

  std::vector<int64_t> alive, done;
  const int steps = *rc::gen::inRange(2, 6);
  for (int step = 0; step < steps; ++step) {
    const int op = alive.empty() ? 0 : *rc::gen::inRange(0, 5);
    const std::string file = testing::WritePolygons(
        dir, std::string("f") + std::to_string(step) + ".geojson", {{RandomRing()}});
    Result<PolygonAddReport> report = Status::Ok();
    const size_t k = alive.empty() ? 0 : *rc::gen::inRange<size_t>(0, alive.size());
    if (op <= 2) {
      PolygonAddOptions o;
      o.surface = "terrain";
      o.file = file;
      o.mode = RandomMode();
      o.tag = std::string("t") + std::to_string(step);
      if (o.mode == FeatureMode::kReplace) o.level = *rc::gen::inRange(300, 700);
      report = AddPolygons(store, o);
      if (report.ok()) alive.push_back(report->first_feature_id);
    } else if (op == 3) {
      PolygonAddOptions o;
      o.file = file;
      report = UpdatePolygon(store, alive[k], o);
      if (report.ok()) alive[k] = report->first_feature_id;
    } else {
      report = RemovePolygon(store, alive[k]);
      if (report.ok()) alive.erase(alive.begin() + static_cast<std::ptrdiff_t>(k));
    }
    if (!report.ok() && report.status().code() != StatusCode::kInvalidArgument)
      RC_FAIL(std::string("step ") + std::to_string(step) + ": " + report.status().ToString());
    if (report.ok()) done.push_back(report->tx);
  }
  RC_CLASSIFY(done.size() >= 3, "3 or more edits");
  for (auto it = done.rbegin(); it != done.rend(); ++it) {
    auto reverted = RevertTransaction(store, *it, {});
    if (!reverted.ok())
      RC_FAIL(std::string("revert ") + std::to_string(*it) + ": " + reverted.status().ToString());
    AssertIntact(store, std::string("after reverting ") + std::to_string(*it));
  }
  const testing::SurfaceSignature back = testing::SignatureOf(store);
  RC_ASSERT(back.features == original.features);
  RC_CLASSIFY(back.vertices == original.vertices, "same vertices as the original");
}

}  // namespace
}  // namespace tinbase
