#include "core/raster/block_codec.h"

#include <blosc.h>
#include <zlib.h>

#include <array>
#include <bit>
#include <cstring>
#include <string>

namespace tinbase {

namespace {

static_assert(std::endian::native == std::endian::little,
              "blocks are stored little-endian; add byte swapping for this platform");

constexpr int kBloscLevel = 5;  // zstd level 5: most of level 9's ratio at a fraction of its time
constexpr size_t kCrcBytes = 4;

// zlib's CRC-32 (the IEEE polynomial, as the table-driven loop this replaced): several times
// faster, and the decode path checks 256 KiB per block.
uint32_t Crc32(const uint8_t* data, size_t size) {
  uLong crc = crc32(0L, Z_NULL, 0);
  while (size > 0) {
    const uInt chunk = static_cast<uInt>(std::min<size_t>(size, 1u << 30));
    crc = crc32(crc, data, chunk);
    data += chunk;
    size -= chunk;
  }
  return static_cast<uint32_t>(crc);
}

}  // namespace

std::vector<uint8_t> EncodeBlock(std::span<const float> cells, BlockCodec /*codec*/) {
  const size_t nbytes = cells.size_bytes();
  std::vector<uint8_t> out(nbytes + BLOSC_MAX_OVERHEAD + kCrcBytes);
  const int written =
      blosc_compress_ctx(kBloscLevel, BLOSC_SHUFFLE, sizeof(float), nbytes, cells.data(),
                         out.data(), nbytes + BLOSC_MAX_OVERHEAD, BLOSC_ZSTD_COMPNAME, 0, 1);
  // With a destination of nbytes + BLOSC_MAX_OVERHEAD Blosc always succeeds (blosc.h).
  out.resize(static_cast<size_t>(written));
  const uint32_t crc = Crc32(reinterpret_cast<const uint8_t*>(cells.data()), nbytes);
  for (size_t i = 0; i < kCrcBytes; ++i) out.push_back(static_cast<uint8_t>(crc >> (8 * i)));
  return out;
}

Result<std::vector<float>> DecodeBlock(int codec, std::span<const uint8_t> data, size_t count) {
  if (codec != static_cast<int>(BlockCodec::kBloscZstd))
    return Status::InvalidArgument("unknown block codec " + std::to_string(codec));
  const size_t expected = count * sizeof(float);
  if (data.size() < BLOSC_MIN_HEADER_LENGTH + kCrcBytes)
    return Status::Corruption("block of " + std::to_string(data.size()) + " bytes is too short");
  const size_t frame = data.size() - kCrcBytes;
  size_t nbytes = 0;
  if (blosc_cbuffer_validate(data.data(), frame, &nbytes) != 0)
    return Status::Corruption("block is not a valid Blosc frame");
  if (nbytes != expected)
    return Status::Corruption("block holds " + std::to_string(nbytes) + " bytes, expected " +
                              std::to_string(expected));
  std::vector<float> cells(count);
  const int got = blosc_decompress_ctx(data.data(), cells.data(), expected, 1);
  if (got < 0 || static_cast<size_t>(got) != expected)
    return Status::Corruption("block does not decompress (Blosc error " + std::to_string(got) +
                              ")");
  uint32_t stored = 0;
  for (size_t i = 0; i < kCrcBytes; ++i)
    stored |= static_cast<uint32_t>(data[frame + i]) << (8 * i);
  if (stored != Crc32(reinterpret_cast<const uint8_t*>(cells.data()), expected))
    return Status::Corruption("block fails its checksum");
  return cells;
}

}  // namespace tinbase
