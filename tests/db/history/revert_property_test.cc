// Issue 28's property: a random sequence of edits (add, update, remove of polygons in every
// painting mode, and points add and remove) followed by the revert of each, in reverse order,
// returns exactly the original surface: the full check passes after every revert, every revert is
// exact (from the mesh images), and at the end the features and every triangle, vertex and
// constraint row (vertices, neighbours, visibility, tags; tests/db/history/surface_signature.h)
// are those the surface had. RapidCheck prints the seed of a failure.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "db/edit/mass_points.h"
#include "db/history/revert.h"
#include "db/polygon_editor.h"
#include "tests/db/history/surface_signature.h"
#include "tests/support/edit_property_fixture.h"

namespace tinbase {
namespace {

using testing::TempDir;

// RapidCheck reads RC_PARAMS on first use; a user's setting wins.
const bool kDefaultParams = [] {
  setenv("RC_PARAMS", "max_success=10", /*overwrite=*/0);
  return true;
}();

// One to five survey points around a random centre, z well inside the DEM's relief.
PointsAddOptions RandomPoints(int step) {
  PointsAddOptions o;
  o.surface = "terrain";
  o.points.emplace();
  const auto [x, y] = testing::RandomCentre();
  const int n = *rc::gen::inRange(1, 6);
  for (int k = 0; k < n; ++k) {
    const double dx = *rc::gen::inRange(-300, 301) / 100.0 * testing::kPropertyCell;
    const double dy = *rc::gen::inRange(-300, 301) / 100.0 * testing::kPropertyCell;
    o.points->push_back({x + dx, y + dy, 600.0 + *rc::gen::inRange(0, 100), VertexKind::kUser});
    o.labels.push_back("step " + std::to_string(step) + " point " + std::to_string(k));
  }
  return o;
}

// One random edit of `store`: its transaction, or 0 when the input was refused (a generated ring
// may fold back; points may snap). `polygons` and `points` hold the live features of each kind.
int64_t RandomEdit(Store& store, const TempDir& dir, int step, std::vector<int64_t>& polygons,
                   std::vector<int64_t>& points) {
  const int op = *rc::gen::inRange(0, 7);
  const std::string what = "step " + std::to_string(step);
  const std::string file = testing::WritePolygons(dir, "f" + std::to_string(step) + ".geojson",
                                                  {{testing::RandomStarRing()}});
  Result<int64_t> tx = int64_t{0};
  if (op == 5 || (op == 6 && points.empty())) {
    auto report = AddPoints(store, RandomPoints(step));
    if (report.ok()) points.push_back(report->features_added.front());
    tx = report.ok() ? Result<int64_t>(report->tx) : Result<int64_t>(report.status());
  } else if (op == 6) {
    const size_t k = *rc::gen::inRange<size_t>(0, points.size());
    PointsRemoveOptions o;
    o.feature = points[k];
    auto report = RemovePoints(store, o);
    if (report.ok()) points.erase(points.begin() + static_cast<std::ptrdiff_t>(k));
    tx = report.ok() ? Result<int64_t>(report->tx) : Result<int64_t>(report.status());
  } else {
    Result<PolygonAddReport> report = Status::Ok();
    const size_t k = polygons.empty() ? 0 : *rc::gen::inRange<size_t>(0, polygons.size());
    if (op <= 2 || polygons.empty()) {
      PolygonAddOptions o;
      o.surface = "terrain";
      o.file = file;
      o.mode = testing::RandomPaintMode(7);
      o.tag = "t" + std::to_string(step);
      if (o.mode == FeatureMode::kReplace) o.level = *rc::gen::inRange(300, 700);
      report = AddPolygons(store, o);
      if (report.ok()) polygons.push_back(report->first_feature_id);
    } else if (op == 3) {
      PolygonAddOptions o;
      o.file = file;
      report = UpdatePolygon(store, polygons[k], o);
      if (report.ok()) polygons[k] = report->first_feature_id;
    } else {
      report = RemovePolygon(store, polygons[k]);
      if (report.ok()) polygons.erase(polygons.begin() + static_cast<std::ptrdiff_t>(k));
    }
    tx = report.ok() ? Result<int64_t>(report->tx) : Result<int64_t>(report.status());
  }
  if (!tx.ok() && tx.status().code() != StatusCode::kInvalidArgument)
    RC_FAIL(what + ": " + tx.status().ToString());
  return tx.ok() ? *tx : 0;
}

RC_GTEST_PROP(RevertProperty, EditsThenRevertsInReverseOrderGiveTheOriginalBack, ()) {
  TempDir dir;
  const std::unique_ptr<Store> opened = testing::OpenCopyOfBaseStore(dir);
  Store& store = *opened;
  const testing::SurfaceSignature original = testing::SignatureOf(store);

  std::vector<int64_t> polygons, points, done;
  const int steps = *rc::gen::inRange(2, 7);
  for (int step = 0; step < steps; ++step) {
    const int64_t tx = RandomEdit(store, dir, step, polygons, points);
    if (tx != 0) done.push_back(tx);
  }
  RC_CLASSIFY(done.size() >= 3, "3 or more edits");
  for (auto it = done.rbegin(); it != done.rend(); ++it) {
    auto reverted = RevertTransaction(store, *it, {});
    if (!reverted.ok())
      RC_FAIL("revert " + std::to_string(*it) + ": " + reverted.status().ToString());
    if (!reverted->exact)
      RC_FAIL("revert " + std::to_string(*it) + " was not exact: " + reverted->not_exact);
    testing::AssertIntact(store, "after reverting " + std::to_string(*it));
  }
  const std::string difference = testing::MeshDifference(original, testing::SignatureOf(store));
  if (!difference.empty()) RC_FAIL("after every revert: " + difference);
}

}  // namespace
}  // namespace tinbase
