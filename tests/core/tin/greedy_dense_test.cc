// Greedy insertion on rough terrain, where most faces end up half a cell in area (the refiner
// reads such a face's three corner cells instead of scanning it): the bound holds on every cell,
// and the TIN is the one the full scan of every face built before that shortcut existed.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>

#include "core/tin/greedy_builder.h"
#include "core/tin/tin_hash.h"
#include "core/tin/tin_raster.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

// A slope plus up to 2 m of white noise in 1 cm steps, from the raw bits of a seeded mt19937
// (its output, unlike the standard distributions', is the same on every standard library).
Grid NoisyGrid(int64_t size) {
  Grid grid;
  grid.geometry = GridGeometry{500000, 5200000, 30, -30, size, size};
  std::mt19937 rng(30);
  for (int64_t r = 0; r < size; ++r)
    for (int64_t c = 0; c < size; ++c)
      grid.cells.push_back(static_cast<float>(0.5 * c + 0.25 * r + (rng() % 201) / 100.0));
  return grid;
}

TEST(GreedyDenseTest, RoughTerrainKeepsTheBoundAndTheTinOfTheFullScan) {
  const Grid dem = NoisyGrid(129);
  // The hashes of the TINs built by the code before issue 30 (every face scanned, a
  // std::priority_queue of candidates), unsplit and split.
  const struct {
    GreedySplit split;
    uint64_t hash;
  } cases[] = {{GreedySplit::kNever, 0x6a177e437d9b3b12ULL},
               {GreedySplit::kAlways, 0xac23bdc9cc830738ULL}};
  for (const auto& [split, hash] : cases) {
    GreedyReport report;
    auto tin = BuildGreedyTin(dem, {.tolerance = 0.3, .split = split}, &report);
    ASSERT_TRUE(tin.ok()) << tin.status().ToString();
    // Dense: more than a third of the cells are vertices.
    EXPECT_GT(tin->vertices.size(), 129u * 129u / 3);
    const TinGridError e = CompareTinToGrid(*tin, dem);
    EXPECT_LE(e.max_error, 0.3);
    EXPECT_EQ(e.uncovered, 0);
    EXPECT_EQ(report.max_error, e.max_error);
    EXPECT_EQ(TinHash(*tin), hash) << std::hex << TinHash(*tin);
  }
}

}  // namespace
}  // namespace tinbase
