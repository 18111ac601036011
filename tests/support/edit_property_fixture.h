// The fixture the property tests of the edit path share (tests/db/update_engine_property_test.cc,
// tests/db/history/revert_property_test.cc): the Hamersley store with its greedy surface at 5 m,
// built once per binary and copied for each case; random star-shaped rings and painting modes
// near the DEM's centre; the full check as a property assertion. The generators call RapidCheck,
// so they are used inside a property. Header-only.
#pragma once

#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>

#include "core/tin/feature_mode.h"
#include "db/dem_store.h"
#include "db/integrity_check.h"
#include "db/store.h"
#include "db/surface_builder.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {

// Centre of the Hamersley DEM (EPSG:28350), and its cell size.
inline constexpr double kPropertyCx = 539300, kPropertyCy = 7497340;
inline constexpr double kPropertyCell = 344.404386931320971;

// The Hamersley store with its greedy surface "terrain" (tolerance 5), built once.
inline const std::string& BaseEditStore() {
  static TempDir dir;
  static const std::string path = [] {
    const std::string p = StoreTarget(dir, "base.tinbase");
    auto store = Store::Create(p, "");
    EXPECT_TRUE(store.ok());
    DemStore dems(**store);
    EXPECT_TRUE(dems.Import({DataPath("geology/hamersley/dtm_rp.tif")}, {}).ok());
    SurfaceBuildOptions o;
    o.surface = "terrain";
    o.greedy.tolerance = 5;
    EXPECT_TRUE(BuildSurfaceFromDem(**store, o).ok());
    return p;
  }();
  return path;
}

// A private copy of the base store in `dir`, opened: each case edits its own.
inline std::unique_ptr<Store> OpenCopyOfBaseStore(const TempDir& dir) {
  const std::string path = StoreTarget(dir, "p.tinbase");
  testing::CopyStore(BaseEditStore(), path);
  auto opened = Store::Open(path);
  RC_ASSERT(opened.ok());
  return std::move(*opened);
}

// A star-shaped (so simple) ring of n vertices around (x, y).
inline PointList StarRing(double x, double y, double radius, int n) {
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

// A random point of the 25 x 25 lattice (0.77 cells apart) around the DEM's centre.
inline std::pair<double, double> RandomCentre() {
  const double x = kPropertyCx + *rc::gen::inRange(-12, 13) * kPropertyCell * 0.77;
  const double y = kPropertyCy + *rc::gen::inRange(-12, 13) * kPropertyCell * 0.77;
  return {x, y};
}

// A star ring of 4 to 24 vertices and a radius of 2 to 10 cells around a RandomCentre.
inline PointList RandomStarRing() {
  const auto [x, y] = RandomCentre();
  const double radius = *rc::gen::inRange(2, 11) * kPropertyCell;
  const int n = *rc::gen::inRange(4, 25);
  return StarRing(x, y, radius, n);
}

// Erase, clip and replace once each in `choices` draws, fill otherwise.
inline FeatureMode RandomPaintMode(int choices) {
  switch (*rc::gen::inRange(0, choices)) {
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

// Fails the property with the first problem of the full check.
inline void AssertIntact(Store& store, const std::string& after) {
  auto problems = CheckStore(store, {.surface = {}, .full = true});
  RC_ASSERT(problems.ok());
  if (!problems->empty())
    RC_FAIL(after + ": " + std::to_string(problems->size()) + " problems, first " +
            problems->front().code + ": " + problems->front().message);
}

}  // namespace tinbase::testing
