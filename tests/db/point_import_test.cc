// ImportPoints end to end: LAS files into a store, CRS adopted or reprojected, thinned or not,
// the surface read back and checked, and failures that leave the store untouched.
//
// Needs db/surface_store.cc and db/integrity_check.cc, written on other branches: in the lidar
// branch alone this executable does not link.
#include "db/point_import.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <random>

#include "db/integrity_check.h"
#include "db/surface_store.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/thread_count.h"
#include "tests/support/tin_checks.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::TempDir;

std::unique_ptr<Store> NewStore(const TempDir& dir, const std::string& crs) {
  auto store = Store::Create(testing::StoreTarget(dir, "points.tinbase"), crs);
  EXPECT_TRUE(store.ok()) << store.status().ToString();
  return store.ok() ? std::move(store).value() : nullptr;
}

void ExpectStoreIntact(Store& store) {
  auto problems = CheckStore(store);
  ASSERT_TRUE(problems.ok()) << problems.status().ToString();
  for (const Problem& p : *problems) ADD_FAILURE() << p.code << ": " << p.message;
}

PointImportOptions Options(const std::string& file, const std::string& surface) {
  PointImportOptions o;
  o.file = DataPath(file);
  o.surface = surface;
  return o;
}

TEST(PointImport, AutzenIntoAnEmptyStoreAdoptsTheFileCrs) {
  TempDir dir;
  auto store = NewStore(dir, "");
  ASSERT_TRUE(store);
  auto report = ImportPoints(*store, Options("las/autzen_trim.las", "autzen"));
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_TRUE(report->adopted_crs);
  EXPECT_EQ(report->points.classes, "ground (class 2)");

  auto crs = store->GetCrs();
  ASSERT_TRUE(crs.ok() && crs->has_value());
  EXPECT_FALSE((*crs)->IsGeographic());

  SurfaceStore surfaces(*store);
  auto info = surfaces.Find("autzen");
  ASSERT_TRUE(info.ok()) << info.status().ToString();
  EXPECT_EQ(info->id, report->surface_id);
  EXPECT_EQ(info->kind, SurfaceKind::kDelaunay);
  EXPECT_EQ(info->method, "lidar");
  auto counts = surfaces.Count(*info);
  ASSERT_TRUE(counts.ok());
  EXPECT_EQ(counts->vertices, static_cast<int64_t>(report->points.kept));
  EXPECT_EQ(counts->triangles, static_cast<int64_t>(report->points.triangles));

  auto loaded = surfaces.Load(*info);
  ASSERT_TRUE(loaded.ok());
  testing::ExpectCounterClockwise(loaded->tin);
  testing::ExpectNeighboursConsistent(loaded->tin);
  testing::ExpectLocallyDelaunay(loaded->tin);
  for (const TinVertex& v : loaded->tin.vertices) ASSERT_EQ(v.kind, VertexKind::kLidar);
  ExpectStoreIntact(*store);
}

TEST(PointImport, ReprojectsIntoTheStoreCrs) {
  TempDir dir;
  auto store = NewStore(dir, "EPSG:32613");
  ASSERT_TRUE(store);
  auto report = ImportPoints(*store, Options("las/4_6_crop.las", "crop"));
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_FALSE(report->adopted_crs);
  EXPECT_EQ(report->points.reprojected_from, "EPSG:2903");
  EXPECT_EQ(report->crs, "EPSG:32613");
  ExpectStoreIntact(*store);
}

TEST(PointImport, ThinnedSurfaceIsSmaller) {
  TempDir dir;
  auto store = NewStore(dir, "");
  ASSERT_TRUE(store);
  auto plain = ImportPoints(*store, Options("las/autzen_trim.las", "plain"));
  PointImportOptions o = Options("las/autzen_trim.las", "thinned");
  o.thin = true;
  o.thresholds.max_cell_area = 15;
  auto thinned = ImportPoints(*store, o);
  ASSERT_TRUE(plain.ok() && thinned.ok()) << thinned.status().ToString();
  EXPECT_GT(thinned->points.dropped, 0u);
  EXPECT_LT(thinned->points.triangles, plain->points.triangles);
  auto info = SurfaceStore(*store).Find("thinned");
  ASSERT_TRUE(info.ok());
  EXPECT_EQ(info->method, "lidar-voronoi-thinned");
  ExpectStoreIntact(*store);
}

// An import big enough to be triangulated in bands (its triangle rows written while the next band
// is inserted, neighbours on a band's edge linked late) stores a checked Delaunay surface.
TEST(PointImport, BandedImportOfAnXyzFile) {
  TempDir dir;
  auto store = NewStore(dir, "EPSG:32632");
  ASSERT_TRUE(store);
  const size_t points = 30000;
  {
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> coord(0, 200);
    std::ofstream out(dir.Path("cloud.xyz"));
    out.precision(12);
    for (size_t i = 0; i < points; ++i) {
      const double x = coord(rng), y = coord(rng);
      out << 500000 + x << " " << 5200000 + y << " " << 300 + std::sin(x / 9) * y / 50 << "\n";
    }
  }
  PointImportOptions options;
  options.file = dir.Path("cloud.xyz");
  options.surface = "cloud";
  auto report = ImportPoints(*store, options);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->points.kept, points);
  SurfaceStore surfaces(*store);
  auto info = surfaces.Find("cloud");
  ASSERT_TRUE(info.ok());
  auto counts = surfaces.Count(*info);
  ASSERT_TRUE(counts.ok());
  EXPECT_EQ(counts->vertices, static_cast<int64_t>(points));
  EXPECT_EQ(counts->triangles, static_cast<int64_t>(report->points.triangles));
  EXPECT_GT(report->points.triangles, 2 * points - 200);
  ExpectStoreIntact(*store);
}

// An import large enough for the sort in halves and the banded triangulation, with duplicate
// points (the first of each is kept), stores the same rows on 1, 2 and 4 threads.
TEST(PointImport, SameSurfaceOnAnyNumberOfThreads) {
  TempDir dir;
  const size_t points = 120000;
  {
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> coord(0, 400);
    std::ofstream out(dir.Path("cloud.xyz"));
    out.precision(12);
    for (size_t i = 0; i < points; ++i) {
      // Every 50th point repeats an x, y of before with another z.
      const double x = i % 50 == 49 ? std::floor(coord(rng)) : coord(rng);
      const double y = i % 50 == 49 ? std::floor(coord(rng)) : coord(rng);
      out << 500000 + x << " " << 5200000 + y << " " << 300 + std::sin(x / 9) * y / 50 << "\n";
      if (i % 1000 == 0) out << 500000 + x << " " << 5200000 + y << " " << 1.0 * i << "\n";
    }
  }
  int runs = 0;
  const auto import = [&](int threads) {
    const std::string path = dir.Path("run" + std::to_string(++runs) + ".tinbase");
    {
      auto store = Store::Create(path, "EPSG:32632");
      EXPECT_TRUE(store.ok()) << store.status().ToString();
      if (!store.ok()) return std::map<std::string, std::string>();
      PointImportOptions options;
      options.file = dir.Path("cloud.xyz");
      options.surface = "cloud";
      auto report = testing::WithThreads(threads, [&] { return ImportPoints(**store, options); });
      EXPECT_TRUE(report.ok()) << report.status().ToString();
      if (report.ok()) {
        EXPECT_GT(report->points.duplicates, 0u);
      }
      ExpectStoreIntact(**store);
    }
    const std::map<std::string, std::string> sums = testing::TableChecksums(path);
    return std::map<std::string, std::string>{{"vertices", sums.at("vertices")},
                                              {"triangles", sums.at("triangles")}};
  };
  const auto want = import(1);
  for (int threads : testing::kThreadCounts) EXPECT_EQ(import(threads), want) << threads;
}

TEST(PointImport, FailuresWriteNothing) {
  TempDir dir;
  auto store = NewStore(dir, "");
  ASSERT_TRUE(store);
  ASSERT_TRUE(ImportPoints(*store, Options("las/mvk-thin.las", "mvk")).ok());
  const auto before = testing::TableChecksums(store->path());

  auto taken = ImportPoints(*store, Options("las/mvk-thin.las", "mvk"));
  EXPECT_EQ(taken.status().code(), StatusCode::kConflict);
  auto unnamed = ImportPoints(*store, Options("las/mvk-thin.las", ""));
  EXPECT_EQ(unnamed.status().code(), StatusCode::kInvalidArgument);
  PointImportOptions none = Options("las/mvk-thin.las", "none");
  none.classes = {31};
  EXPECT_EQ(ImportPoints(*store, none).status().code(), StatusCode::kInvalidArgument);
  auto missing = ImportPoints(*store, Options("las/missing.las", "missing"));
  EXPECT_EQ(missing.status().code(), StatusCode::kIOError);

  EXPECT_EQ(testing::TableChecksums(store->path()), before);
  ExpectStoreIntact(*store);
}

}  // namespace
}  // namespace tinbase
