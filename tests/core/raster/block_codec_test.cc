// Block codec: float32 blocks survive encode/decode bit for bit (NaN included); damaged bytes
// give Corruption, never wrong elevations.
#include "core/raster/block_codec.h"

#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>

namespace tinbase {
namespace {

std::vector<uint32_t> Bits(const std::vector<float>& cells) {
  std::vector<uint32_t> bits(cells.size());
  if (!cells.empty()) std::memcpy(bits.data(), cells.data(), cells.size() * sizeof(float));
  return bits;
}

// A terrain-like block: a smooth surface with noise, nodata holes and special values.
std::vector<float> TerrainBlock(int size, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0, 0.5f);
  std::vector<float> cells(static_cast<size_t>(size) * size);
  for (int r = 0; r < size; ++r)
    for (int c = 0; c < size; ++c)
      cells[static_cast<size_t>(r * size + c)] = 800 + 3.5f * r - 1.25f * c + noise(rng);
  for (int i = 0; i < size * 3; ++i) cells[rng() % cells.size()] = std::nanf("");
  cells[0] = -0.0f;
  cells[1] = std::numeric_limits<float>::infinity();
  cells[2] = std::numeric_limits<float>::denorm_min();
  return cells;
}

TEST(BlockCodec, RoundTripKeepsEveryBitIncludingNaN) {
  const std::vector<float> cells = TerrainBlock(256, 7);
  const std::vector<uint8_t> bytes = EncodeBlock(cells);
  auto decoded = DecodeBlock(static_cast<int>(BlockCodec::kBloscZstd), bytes, cells.size());
  ASSERT_TRUE(decoded.ok()) << decoded.status().ToString();
  EXPECT_EQ(Bits(*decoded), Bits(cells));
  EXPECT_LT(bytes.size(), cells.size() * sizeof(float));  // shuffle + zstd does compress terrain
}

TEST(BlockCodec, AllNodataBlockIsTiny) {
  const std::vector<float> cells(256 * 256, std::nanf(""));
  const std::vector<uint8_t> bytes = EncodeBlock(cells);
  EXPECT_LT(bytes.size(), 1024u);
  auto decoded = DecodeBlock(1, bytes, cells.size());
  ASSERT_TRUE(decoded.ok());
  for (float v : *decoded) ASSERT_TRUE(std::isnan(v));
}

TEST(BlockCodec, RoundTripOfArbitraryBlocks) {
  // RapidCheck prints the seed of a failing case; rerun with RC_PARAMS="seed=..." to reproduce.
  const bool ok =
      rc::check("decode(encode(cells)) == cells", [](const std::vector<uint32_t>& bits) {
        std::vector<float> cells(bits.size());
        if (!bits.empty()) std::memcpy(cells.data(), bits.data(), bits.size() * sizeof(float));
        auto decoded = DecodeBlock(1, EncodeBlock(cells), cells.size());
        RC_ASSERT(decoded.ok());
        RC_ASSERT(Bits(*decoded) == bits);
      });
  EXPECT_TRUE(ok);
}

// Some bits of a Blosc/zstd frame do not take part in decoding (flags zstd ignores), so a flip
// there may still give the original cells; what must never happen is different cells.
TEST(BlockCodec, DamagedBytesGiveCorruptionNeverOtherCells) {
  const std::vector<float> cells = TerrainBlock(32, 11);
  const std::vector<uint8_t> bytes = EncodeBlock(cells);
  int corrupt = 0;
  int harmless = 0;
  for (size_t i = 0; i < bytes.size(); ++i) {
    for (uint8_t flip : {uint8_t{0x01}, uint8_t{0x10}, uint8_t{0x80}}) {
      std::vector<uint8_t> damaged = bytes;
      damaged[i] ^= flip;
      auto decoded = DecodeBlock(1, damaged, cells.size());
      if (decoded.ok()) {
        ASSERT_EQ(Bits(*decoded), Bits(cells)) << "byte " << i << " flip " << int(flip);
        ++harmless;
        continue;
      }
      ++corrupt;
      EXPECT_EQ(decoded.status().code(), StatusCode::kCorruption)
          << "byte " << i << ": " << decoded.status().ToString();
    }
  }
  std::printf("%d damaged frames rejected, %d decoded to the original\n", corrupt, harmless);
  EXPECT_GT(corrupt, 20 * harmless);
}

TEST(BlockCodec, TruncatedOrMislabelledInputIsRejected) {
  const std::vector<float> cells = TerrainBlock(64, 3);
  const std::vector<uint8_t> bytes = EncodeBlock(cells);
  for (size_t keep : {size_t{0}, size_t{5}, size_t{16}, bytes.size() / 2, bytes.size() - 1}) {
    auto decoded = DecodeBlock(1, std::span(bytes.data(), keep), cells.size());
    ASSERT_FALSE(decoded.ok()) << keep;
    EXPECT_EQ(decoded.status().code(), StatusCode::kCorruption) << keep;
  }
  auto wrong_count = DecodeBlock(1, bytes, cells.size() / 2);
  EXPECT_EQ(wrong_count.status().code(), StatusCode::kCorruption);
  auto unknown = DecodeBlock(99, bytes, cells.size());
  EXPECT_EQ(unknown.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(unknown.status().message().find("99"), std::string::npos);
}

}  // namespace
}  // namespace tinbase
