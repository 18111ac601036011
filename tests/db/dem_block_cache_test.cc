// DemBlockCache: LRU by bytes, null entries, per-store erasure, safe under concurrent use; and
// DemStore sampling through it from several threads, each with its own Store, under a limit small
// enough to force evictions, against the analytic plane the test DEM was generated from.
#include "db/dem_block_cache.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <random>
#include <thread>

#include "db/dem_store.h"
#include "db/store.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

DemBlockCache::Block BlockOf(size_t cells, float value) {
  return std::make_shared<const std::vector<float>>(cells, value);
}

DemBlockKey Key(int64_t bx, uint64_t store = 1) { return DemBlockKey{store, 1, 0, bx, 0}; }

TEST(DemBlockCache, EvictsTheLeastRecentlyUsedBeyondTheByteLimit) {
  const size_t charge = DemBlockCache::Charge(BlockOf(1024, 0));
  DemBlockCache cache(3 * charge);
  for (int i = 0; i < 3; ++i) cache.Insert(Key(i), BlockOf(1024, static_cast<float>(i)));
  DemBlockCache::Block got;
  ASSERT_TRUE(cache.Lookup(Key(0), &got));  // 0 is now the most recent; 1 the least
  EXPECT_EQ((*got)[0], 0.0f);
  cache.Insert(Key(3), BlockOf(1024, 3));
  EXPECT_FALSE(cache.Lookup(Key(1), &got));
  for (int i : {0, 2, 3}) {
    ASSERT_TRUE(cache.Lookup(Key(i), &got)) << i;
    EXPECT_EQ((*got)[1023], static_cast<float>(i));
  }
  const auto stats = cache.stats();
  EXPECT_EQ(stats.entries, 3u);
  EXPECT_EQ(stats.bytes, 3 * charge);
  EXPECT_EQ(stats.evictions, 1);
  EXPECT_LE(stats.bytes, cache.capacity());
}

TEST(DemBlockCache, NullBlocksAreCachedAndOversizedBlocksAreNot) {
  DemBlockCache cache(DemBlockCache::Charge(BlockOf(100, 0)));
  cache.Insert(Key(0), nullptr);
  DemBlockCache::Block got = BlockOf(1, 1);
  ASSERT_TRUE(cache.Lookup(Key(0), &got));
  EXPECT_EQ(got, nullptr);
  cache.Insert(Key(1), BlockOf(101, 0));  // larger than the whole limit
  EXPECT_FALSE(cache.Lookup(Key(1), &got));
  // A kept block stays valid for its holder after eviction.
  cache.Insert(Key(2), BlockOf(100, 7));
  ASSERT_TRUE(cache.Lookup(Key(2), &got));
  cache.SetCapacity(0);
  EXPECT_EQ(cache.stats().entries, 0u);
  EXPECT_EQ((*got)[99], 7.0f);
}

TEST(DemBlockCache, EraseStoreDropsOnlyThatStoresEntries) {
  DemBlockCache cache;
  for (int i = 0; i < 4; ++i) {
    cache.Insert(Key(i, 10), BlockOf(16, 1));
    cache.Insert(Key(i, 20), BlockOf(16, 2));
  }
  cache.EraseStore(10);
  DemBlockCache::Block got;
  for (int i = 0; i < 4; ++i) {
    EXPECT_FALSE(cache.Lookup(Key(i, 10), &got));
    ASSERT_TRUE(cache.Lookup(Key(i, 20), &got));
    EXPECT_EQ((*got)[0], 2.0f);
  }
  EXPECT_EQ(cache.stats().bytes, 4 * DemBlockCache::Charge(BlockOf(16, 0)));
}

// Threads insert and look up overlapping keys; every hit must hold the block of its own key and
// the charged bytes must stay within the limit.
TEST(DemBlockCache, ConcurrentUseKeepsEntriesAndLimit) {
  const size_t charge = DemBlockCache::Charge(BlockOf(256, 0));
  DemBlockCache cache(40 * charge);
  std::atomic<int64_t> hits{0};
  std::atomic<bool> wrong{false};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      std::mt19937 rng(1234 + t);
      std::uniform_int_distribution<int> pick(0, 99);
      for (int i = 0; i < 20000; ++i) {
        const int k = pick(rng);
        DemBlockCache::Block got;
        if (cache.Lookup(Key(k), &got)) {
          ++hits;
          if (got == nullptr || (*got)[255] != static_cast<float>(k)) wrong = true;
        } else {
          cache.Insert(Key(k), BlockOf(256, static_cast<float>(k)));
        }
        if (cache.stats().bytes > 40 * charge) wrong = true;
      }
    });
  for (auto& th : threads) th.join();
  EXPECT_FALSE(wrong);
  EXPECT_GT(hits, 0);
  std::printf("concurrent cache: %lld hits of 80000\n", static_cast<long long>(hits.load()));
}

// A 600 x 500 Float32 GeoTIFF of the plane z = col + 1000 row (exact in float32), 10 m cells;
// cells with (col / 50 + row / 50) % 7 == 3 are nodata (-9999) so whole blocks go missing.
std::string WritePlane(const TempDir& dir) {
  GDALAllRegister();
  const std::string path = dir.Path("plane.tif");
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  constexpr int kW = 600, kH = 500;
  GDALDataset* ds = gtiff->Create(path.c_str(), kW, kH, 1, GDT_Float32, nullptr);
  double gt[6] = {500000, 10, 0, 5000000, 0, -10};
  ds->SetGeoTransform(gt);
  OGRSpatialReference srs;
  srs.importFromEPSG(32632);
  ds->SetSpatialRef(&srs);
  ds->GetRasterBand(1)->SetNoDataValue(-9999);
  std::vector<float> cells(static_cast<size_t>(kW) * kH);
  for (int r = 0; r < kH; ++r)
    for (int c = 0; c < kW; ++c)
      cells[static_cast<size_t>(r) * kW + c] =
          (c / 50 + r / 50) % 7 == 3 ? -9999.0f : static_cast<float>(c + 1000 * r);
  EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, kW, kH, cells.data(), kW, kH,
                                           GDT_Float32, 0, 0, nullptr),
            CE_None);
  GDALClose(ds);
  return path;
}

bool PlaneValid(int64_t c, int64_t r) { return (c / 50 + r / 50) % 7 != 3; }

TEST(DemSampling, ThreadsWithTheirOwnStoresShareTheCacheUnderEvictions) {
  TempDir dir;
  const std::string plane = WritePlane(dir);
  const std::string path = testing::StoreTarget(dir, "s.tinbase");
  {
    auto store = Store::Create(path, "");
    ASSERT_TRUE(store.ok());
    DemStore dems(**store);
    DemImportOptions options;
    options.name = "plane";
    options.block_size = 32;  // 19 x 16 blocks of 4 KiB
    ASSERT_TRUE(dems.Import({plane}, options).ok());
  }
  DemBlockCache& cache = DemBlockCache::Instance();
  const size_t old_capacity = cache.capacity();
  cache.SetCapacity(24 * DemBlockCache::Charge(BlockOf(32 * 32, 0)));
  std::atomic<int64_t> checked{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      auto store = Store::Open(path, Store::Access::kReadOnly);
      ASSERT_TRUE(store.ok());
      DemStore dems(**store);
      auto dem = dems.Find("plane");
      ASSERT_TRUE(dem.ok());
      std::mt19937 rng(99 + t);
      std::uniform_real_distribution<double> ux(500000, 506000), uy(4995000, 5000000);
      std::vector<double> xs(2000), ys(2000), zs(2000);
      for (int round = 0; round < 3; ++round) {
        for (size_t i = 0; i < xs.size(); ++i) {
          xs[i] = ux(rng);
          ys[i] = uy(rng);
        }
        for (DemSampling method : {DemSampling::kNearest, DemSampling::kBilinear}) {
          ASSERT_TRUE(dems.SampleMany(*dem, xs, ys, zs, method).ok());
          for (size_t i = 0; i < xs.size(); ++i) {
            const double fc = (xs[i] - 500000) / 10, fr = (5000000 - ys[i]) / 10;
            const auto c = static_cast<int64_t>(fc), r = static_cast<int64_t>(fr);
            if (method == DemSampling::kNearest) {
              if (PlaneValid(c, r)) {
                ASSERT_EQ(zs[i], static_cast<double>(c + 1000 * r)) << xs[i] << " " << ys[i];
              } else {
                ASSERT_TRUE(std::isnan(zs[i]));
              }
              continue;
            }
            // Bilinear over four valid cells inside the centres' hull is the plane itself.
            const double cc = fc - 0.5, rr = fr - 0.5;
            const auto c0 = static_cast<int64_t>(std::floor(cc));
            const auto r0 = static_cast<int64_t>(std::floor(rr));
            if (c0 < 0 || r0 < 0 || c0 + 1 >= 600 || r0 + 1 >= 500 || !PlaneValid(c0, r0) ||
                !PlaneValid(c0 + 1, r0) || !PlaneValid(c0, r0 + 1) || !PlaneValid(c0 + 1, r0 + 1))
              continue;
            ASSERT_NEAR(zs[i], cc + 1000 * rr, 1e-6) << xs[i] << " " << ys[i];
            auto single = dems.Sample(*dem, xs[i], ys[i]);
            ASSERT_TRUE(single.ok());
            ASSERT_EQ(*single, zs[i]);
            ++checked;
          }
        }
      }
    });
  for (auto& th : threads) th.join();
  const auto stats = cache.stats();
  cache.SetCapacity(old_capacity);
  EXPECT_GT(checked, 3000);
  EXPECT_GT(stats.evictions, 0);
  EXPECT_LE(stats.bytes, 24 * DemBlockCache::Charge(BlockOf(32 * 32, 0)));
}

}  // namespace
}  // namespace tinbase
