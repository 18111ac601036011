// The page cache grows for a large write and comes back after it; small writes and caches set
// in pages or already larger are left alone.
#include "db/sqlite/scoped_page_cache.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

int64_t CacheSize(Connection& db) { return *db.QueryInt("PRAGMA cache_size"); }

TEST(ScopedPageCacheTest, RaisedForLargeWritesAndRestored) {
  TempDir dir;
  auto db = Connection::Open(dir.Path("c.db"), Connection::Mode::kCreate);
  ASSERT_TRUE(db.ok());
  const int64_t before = CacheSize(**db);
  ASSERT_LT(before, 0);  // SQLite's default is in KiB
  {
    ScopedPageCache small(**db, ScopedPageCache::kThresholdRows - 1);
    EXPECT_FALSE(small.raised());
    EXPECT_EQ(CacheSize(**db), before);
  }
  {
    ScopedPageCache large(**db, ScopedPageCache::kThresholdRows);
    EXPECT_TRUE(large.raised());
    EXPECT_EQ(CacheSize(**db), -ScopedPageCache::kMinCacheKib);
    ScopedPageCache nested(**db, ScopedPageCache::kThresholdRows);
    EXPECT_FALSE(nested.raised()) << "already large enough";
  }
  EXPECT_EQ(CacheSize(**db), before);
}

TEST(ScopedPageCacheTest, GrowsWithTheWriteUpToTheCap) {
  EXPECT_EQ(ScopedPageCache::CacheSizeFor(ScopedPageCache::kThresholdRows),
            -ScopedPageCache::kMinCacheKib);
  const size_t rows = 12'000'000;  // a 4 M point import
  EXPECT_EQ(ScopedPageCache::CacheSizeFor(rows),
            -static_cast<int64_t>(rows / 1024) * ScopedPageCache::kBytesPerRow);
  EXPECT_EQ(ScopedPageCache::CacheSizeFor(size_t{1} << 40), -ScopedPageCache::kMaxCacheKib);
  TempDir dir;
  auto db = Connection::Open(dir.Path("c.db"), Connection::Mode::kCreate);
  ASSERT_TRUE(db.ok());
  {
    ScopedPageCache large(**db, rows);
    EXPECT_TRUE(large.raised());
    EXPECT_EQ(CacheSize(**db), ScopedPageCache::CacheSizeFor(rows));
    ScopedPageCache smaller(**db, rows / 2);
    EXPECT_FALSE(smaller.raised()) << "already large enough";
  }
  EXPECT_LT(CacheSize(**db), 0);
  EXPECT_GT(CacheSize(**db), -ScopedPageCache::kMinCacheKib);
}

TEST(ScopedPageCacheTest, CacheInPagesIsLeftAlone) {
  TempDir dir;
  auto db = Connection::Open(dir.Path("c.db"), Connection::Mode::kCreate);
  ASSERT_TRUE(db.ok());
  ASSERT_TRUE((*db)->Exec("PRAGMA cache_size = 500").ok());
  {
    ScopedPageCache large(**db, 10 * ScopedPageCache::kThresholdRows);
    EXPECT_FALSE(large.raised());
  }
  EXPECT_EQ(CacheSize(**db), 500);
}

}  // namespace
}  // namespace tinbase
