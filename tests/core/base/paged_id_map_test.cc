// PagedIdMap against std::map under random puts, emplaces and erases over ids dense in places,
// sparse in others, past the paged range and negative: the same values, size and iteration.
#include "core/base/paged_id_map.h"

#include <gtest/gtest.h>

#include <map>
#include <random>

namespace tinbase {
namespace {

TEST(PagedIdMapTest, AgreesWithAnOrderedMap) {
  PagedIdMap<int64_t, 4> paged;  // 16 ids a page, so pages fill, empty and go often
  std::map<int64_t, int64_t> reference;
  std::mt19937_64 rng(11);
  const int64_t far = PagedIdMap<int64_t, 4>::kPageSize * PagedIdMap<int64_t, 4>::kMaxPages;
  const auto random_id = [&]() -> int64_t {
    switch (rng() % 5) {
      case 0:
        return static_cast<int64_t>(rng() % 64);  // dense
      case 4:
        return -1 - static_cast<int64_t>(rng() % 32);  // negative (SQLite allows such rowids)
      case 1:
        return static_cast<int64_t>(rng() % 100000);  // sparse
      case 2:
        return far + static_cast<int64_t>(rng() % 32);  // past the pages
      default:
        return 1000 + static_cast<int64_t>(rng() % 40);  // another dense run
    }
  };
  for (int step = 0; step < 20000; ++step) {
    const int64_t id = random_id();
    const int64_t value = static_cast<int64_t>(rng() % 1000);
    switch (rng() % 4) {
      case 0:
        EXPECT_EQ(paged.Put(id, value), reference.count(id) == 0);
        reference[id] = value;
        break;
      case 1:
        EXPECT_EQ(paged.Emplace(id, value), reference.emplace(id, value).first->second);
        break;
      default:
        EXPECT_EQ(paged.Erase(id), reference.erase(id) > 0);
        break;
    }
    const int64_t probe = random_id();
    const int64_t* found = paged.Find(probe);
    ASSERT_EQ(found != nullptr, reference.count(probe) > 0) << probe;
    if (found) {
      EXPECT_EQ(*found, reference.at(probe));
    }
    ASSERT_EQ(paged.size(), reference.size());
  }
  std::map<int64_t, int64_t> seen;
  paged.ForEach([&](int64_t id, int64_t value) { EXPECT_TRUE(seen.emplace(id, value).second); });
  EXPECT_EQ(seen, reference);
  paged.Clear();
  EXPECT_EQ(paged.size(), 0u);
  EXPECT_EQ(paged.Find(reference.begin()->first), nullptr);
}

TEST(PagedIdMapTest, BytesCountPagesInUse) {
  PagedIdMap<int64_t, 4> paged;
  const size_t empty = paged.bytes();
  paged.Put(1, 1);
  const size_t one_page = paged.bytes();
  EXPECT_GT(one_page, empty);
  paged.Put(2, 2);  // same page
  EXPECT_EQ(paged.bytes(), one_page);
  paged.Put(1000, 3);  // another page, further along the page table
  const size_t two_pages = paged.bytes();
  EXPECT_GT(two_pages, one_page);
  paged.Erase(1000);  // its page goes
  const size_t after_one = paged.bytes();
  EXPECT_LT(after_one, two_pages);
  paged.Erase(1);
  EXPECT_EQ(paged.bytes(), after_one);  // 2 still holds the page
  paged.Erase(2);
  EXPECT_LT(paged.bytes(), after_one);
}

}  // namespace
}  // namespace tinbase
