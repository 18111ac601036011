// Property: random sequences of polygon add / update / remove (star-shaped polygons with and
// without holes, overlapping, crossing earlier rings, sharing their vertices and edges, earlier
// rings again; every mode) over the Hamersley DEM keep the store fully intact after each step (all
// eight invariants: CheckStore with `full`), and the stored triangulation is the constrained
// Delaunay triangulation of its vertices and constraints: a from-scratch CGAL CDT of them has as
// many triangles, every constraint is an edge and every other edge is locally Delaunay by the exact
// in-circle test (the check's invariants 4 and 5), which pins the CDT down up to co-circular
// ties (grid points are co-circular everywhere, so triangle sets are not compared).
// RapidCheck prints its seed; RC_PARAMS="seed=..." reproduces a run. Cases default to 12 to
// keep the executable under a minute (RC_PARAMS="max_success=..." for more).
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "core/geometry/cdt.h"
#include "db/dem_store.h"
#include "db/edit/update_engine_test_hooks.h"
#include "db/integrity_check.h"
#include "db/polygon_editor.h"
#include "db/surface_builder.h"
#include "db/surface_store.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::PointList;
using testing::StoreTarget;
using testing::TempDir;

// RapidCheck reads RC_PARAMS on first use; a user's setting wins.
const bool kDefaultParams = [] {
  setenv("RC_PARAMS", "max_success=12", /*overwrite=*/0);
  return true;
}();

constexpr double kCx = 539300, kCy = 7497340, kCell = 344.404386931320971;

// The Hamersley store with its greedy surface, built once and copied for each case.
const std::string& BaseStore() {
  static TempDir dir;
  static const std::string path = [] {
    const std::string p = StoreTarget(dir, "base.tinbase");
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

// A star-shaped (so simple) ring around a point near the DEM's centre.
PointList StarRing(double x, double y, double radius, int n) {
  PointList ring;
  const double phase = *rc::gen::inRange(0, 628) / 100.0;
  for (int k = 0; k < n; ++k) {
    const double r = radius * *rc::gen::inRange(60, 101) / 100.0;
    const double a = phase + 2 * M_PI * k / n;
    ring.push_back({x + r * std::cos(a), y + r * std::sin(a)});
  }
  ring.push_back(ring.front());
  return ring;
}

// A new polygon: a star, maybe with a hole, or (when there is an earlier ring) that ring again,
// or one that takes three consecutive vertices of it and closes with an apex outside.
std::vector<PointList> RandomPolygon(const std::vector<PointList>& earlier) {
  // The same ring again: every point lands on a vertex, every segment on constraints and near
  // the crossings earlier rings made (the CGAL#6602 regression).
  if (!earlier.empty() && *rc::gen::inRange(0, 5) == 0)
    return {earlier[*rc::gen::inRange<size_t>(0, earlier.size())]};
  if (!earlier.empty() && *rc::gen::inRange(0, 4) == 0) {
    const PointList& old = earlier[*rc::gen::inRange<size_t>(0, earlier.size())];
    const size_t i = *rc::gen::inRange<size_t>(0, old.size() - 3);
    double cx = 0, cy = 0;
    for (size_t k = 0; k + 1 < old.size(); ++k) cx += old[k].first, cy += old[k].second;
    cx /= static_cast<double>(old.size() - 1), cy /= static_cast<double>(old.size() - 1);
    const auto& mid = old[i + 1];
    const double dx = mid.first - cx, dy = mid.second - cy;
    return {{old[i], old[i + 1], old[i + 2], {cx + 2.5 * dx, cy + 2.5 * dy}, old[i]}};
  }
  const double x = kCx + *rc::gen::inRange(-12, 13) * kCell * 0.77;
  const double y = kCy + *rc::gen::inRange(-12, 13) * kCell * 0.77;
  const double radius = *rc::gen::inRange(2, 11) * kCell;
  std::vector<PointList> rings{StarRing(x, y, radius, *rc::gen::inRange(4, 25))};
  if (*rc::gen::inRange(0, 3) == 0)
    rings.push_back(testing::Ngon(x, y, 0.35 * radius, *rc::gen::inRange(3, 9)));
  return rings;
}

FeatureMode RandomMode() {
  switch (*rc::gen::inRange(0, 8)) {
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

// A private copy of the base store in `dir`, opened: each case edits its own.
std::unique_ptr<Store> OpenCopyOfBaseStore(const TempDir& dir) {
  const std::string path = StoreTarget(dir, "p.tinbase");
  testing::CopyStore(BaseStore(), path);
  auto opened = Store::Open(path);
  RC_ASSERT(opened.ok());
  return std::move(*opened);
}

// Fails the property with the first problem of the full check.
void AssertIntact(Store& store, const std::string& after) {
  auto problems = CheckStore(store, {.surface = {}, .full = true});
  RC_ASSERT(problems.ok());
  if (!problems->empty())
    RC_FAIL(after + ": " + std::to_string(problems->size()) + " problems, first " +
            problems->front().code + ": " + problems->front().message);
}

// The stored surface has exactly as many triangles as a from-scratch CDT of its vertices and
// constraints (with the full check's invariants 4 and 5 this makes it that CDT).
void AssertSameAsFromScratch(Store& store) {
  SurfaceStore surfaces(store);
  auto surface = surfaces.Find("terrain");
  RC_ASSERT(surface.ok());
  auto loaded = surfaces.Load(*surface);
  RC_ASSERT(loaded.ok());
  Cdt cdt;
  const std::vector<uint32_t> index = cdt.InsertVertices(loaded->tin.vertices);
  for (const auto& [a, b] : loaded->tin.constraints) cdt.InsertConstraint(index[a], index[b]);
  const Tin scratch = cdt.ToTin([](double, double) { return 0.0; });
  RC_ASSERT(scratch.vertices.size() == loaded->tin.vertices.size());  // no new crossings
  RC_ASSERT(scratch.triangles.size() == loaded->tin.triangles.size());
}

RC_GTEST_PROP(UpdateEngineProperty, RandomEditSequencesKeepEveryInvariant, ()) {
  TempDir dir;
  const std::unique_ptr<Store> opened = OpenCopyOfBaseStore(dir);
  Store& store = *opened;
  struct Alive {
    int64_t id;
    std::string mode;
  };
  std::vector<Alive> alive;
  std::vector<PointList> rings;
  const int steps = *rc::gen::inRange(2, 6);
  for (int step = 0; step < steps; ++step) {
    const int op = alive.empty() ? 0 : *rc::gen::inRange(0, 5);
    const std::vector<PointList> polygon = RandomPolygon(rings);
    const std::string file =
        testing::WritePolygons(dir, "f" + std::to_string(step) + ".geojson", {polygon});
    std::string what;
    Result<PolygonAddReport> report = Status::Ok();
    if (op <= 2) {  // add
      PolygonAddOptions o;
      o.surface = "terrain";
      o.file = file;
      o.mode = RandomMode();
      if (o.mode == FeatureMode::kReplace) o.level = *rc::gen::inRange(300, 700);
      what = "step " + std::to_string(step) + ": add " + FeatureModeName(*o.mode);
      report = AddPolygons(store, o);
      if (report.ok()) alive.push_back({report->first_feature_id, FeatureModeName(*o.mode)});
    } else if (op == 3) {  // update
      const size_t k = *rc::gen::inRange<size_t>(0, alive.size());
      PolygonAddOptions o;
      o.file = file;
      what = "step " + std::to_string(step) + ": update feature " + std::to_string(alive[k].id);
      report = UpdatePolygon(store, alive[k].id, o);
      if (report.ok()) alive[k].id = report->first_feature_id;
    } else {  // remove
      const size_t k = *rc::gen::inRange<size_t>(0, alive.size());
      what = "step " + std::to_string(step) + ": remove feature " + std::to_string(alive[k].id);
      report = RemovePolygon(store, alive[k].id);
      if (report.ok()) alive.erase(alive.begin() + static_cast<std::ptrdiff_t>(k));
    }
    RC_CLASSIFY(report.ok(), "applied");
    // A generated ring may be rejected by validation (an apex folding back): that is fine, as
    // long as it is a clear InvalidArgument and the store stays intact.
    if (!report.ok() && report.status().code() != StatusCode::kInvalidArgument)
      RC_FAIL(what + ": " + report.status().ToString());
    if (report.ok() && op != 4) rings.push_back(polygon.front());  // later polygons share it
    AssertIntact(store, what);
    AssertSameAsFromScratch(store);
  }
}

// A load feature by feature (`--each`) of random polygons in one mode, with a failure injected
// at a random write step of a random edit half of the time: every edit that keeps the mesh rows of
// the one before (db/mesh_cache.h) finds them equal to the store (verify_mesh), and the store
// ends fully intact and equal to a from-scratch CDT.
RC_GTEST_PROP(UpdateEngineProperty, LoadsFeatureByFeatureKeepOnlyCurrentRows, ()) {
  TempDir dir;
  const std::unique_ptr<Store> opened = OpenCopyOfBaseStore(dir);
  Store& store = *opened;
  std::vector<std::vector<PointList>> polygons;
  std::vector<PointList> rings;
  const int count = *rc::gen::inRange(3, 8);
  for (int k = 0; k < count; ++k) {
    polygons.push_back(RandomPolygon(rings));
    rings.push_back(polygons.back().front());
  }
  PolygonAddOptions o;
  o.surface = "terrain";
  o.file = testing::WritePolygons(dir, "each.geojson", polygons);
  o.mode = RandomMode();
  if (o.mode == FeatureMode::kReplace) o.level = *rc::gen::inRange(300, 700);
  o.each = true;
  const bool inject = *rc::gen::inRange(0, 2) == 0;
  const int fail_edit = *rc::gen::inRange(1, count + 1);
  const int fail_step = *rc::gen::inRange(1, 8);
  int edits = 0;
  ScopedUpdateEngineTestHooks hooks({[&](int step) {
                                       if (step == 0) ++edits;
                                       return inject && edits == fail_edit && step == fail_step
                                                  ? Status::IOError("injected failure")
                                                  : Status::Ok();
                                     },
                                     /*verify_mesh=*/true});
  auto report = AddPolygons(store, o);
  const std::string what =
      std::string("--each ") + FeatureModeName(*o.mode) + " of " + std::to_string(count);
  if (!report.ok()) {
    // Every feature failed (validation); nothing was written.
    RC_ASSERT(report.status().code() == StatusCode::kInvalidArgument);
  } else {
    for (const std::string& failure : report->failures)
      RC_ASSERT(failure.find("cached") == std::string::npos);
    RC_CLASSIFY(report->mesh_kept > 0, "rows kept");
  }
  AssertIntact(store, what);
  AssertSameAsFromScratch(store);
}

}  // namespace
}  // namespace tinbase
