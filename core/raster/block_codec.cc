#include "core/raster/block_codec.h"

#include <blosc.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <string>

namespace tinbase {

namespace {

static_assert(std::endian::native == std::endian::little,
              "blocks are stored little-endian; add byte swapping for this platform");

constexpr int kShuffleLevel = 5;  // codec 1: zstd level 5, most of level 9's ratio
// Codec 2: residuals compress better and faster than raw floats, so a higher level still imports
// at about the old speed.
constexpr int kPlanarLevel = 5;
constexpr size_t kCrcBytes = 4;
constexpr size_t kWidthBytes = 4;

// zlib's CRC-32 (the IEEE polynomial): the decode path checks every block it reads.
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

void AppendLe32(uint32_t v, std::vector<uint8_t>* out) {
  for (size_t i = 0; i < 4; ++i) out->push_back(static_cast<uint8_t>(v >> (8 * i)));
}

uint32_t ReadLe32(const uint8_t* p) {
  uint32_t v = 0;
  for (size_t i = 0; i < 4; ++i) v |= static_cast<uint32_t>(p[i]) << (8 * i);
  return v;
}

// Float bits as an unsigned key in the order of the values (negative below positive), so that
// nearby elevations have nearby keys and integer differences stay small across zero.
uint32_t KeyOf(float f) {
  const uint32_t u = std::bit_cast<uint32_t>(f);
  const uint32_t negative = static_cast<uint32_t>(static_cast<int32_t>(u) >> 31);
  return u ^ (negative | 0x80000000u);
}
float FloatOfKey(uint32_t k) {
  const uint32_t positive = static_cast<uint32_t>(static_cast<int32_t>(k) >> 31);
  return std::bit_cast<float>(k ^ (~positive | 0x80000000u));
}
uint32_t ZigZag(uint32_t v) {
  return (v << 1) ^ static_cast<uint32_t>(static_cast<int32_t>(v) >> 31);
}
uint32_t UnZigZag(uint32_t z) { return (z >> 1) ^ (0u - (z & 1)); }

// The residuals of codec 2 (wrapping uint32 arithmetic; the decoder wraps the same way). The
// first row is predicted from the west, the first column from the north, the rest by the plane.
std::vector<uint32_t> PlanarResiduals(std::span<const float> cells, size_t width) {
  const size_t n = cells.size();
  std::vector<uint32_t> keys(n), residuals(n);
  for (size_t i = 0; i < n; ++i) keys[i] = KeyOf(cells[i]);
  for (size_t i = 0; i < n; ++i) {
    const size_t col = i % width;
    uint32_t predicted = 0;
    if (i < width)
      predicted = col > 0 ? keys[i - 1] : 0;
    else if (col == 0)
      predicted = keys[i - width];
    else
      predicted = keys[i - 1] + keys[i - width] - keys[i - width - 1];
    residuals[i] = ZigZag(keys[i] - predicted);
  }
  return residuals;
}

// Inverts PlanarResiduals in place: `cells` holds the residuals' bits on entry.
void UndoPlanar(std::span<float> cells, size_t width) {
  uint32_t* k = reinterpret_cast<uint32_t*>(cells.data());
  const size_t n = cells.size();
  for (size_t row_start = 0; row_start < n; row_start += width) {
    const size_t len = std::min(width, n - row_start);
    uint32_t* row = k + row_start;
    if (row_start == 0) {
      uint32_t west = 0;
      for (size_t c = 0; c < len; ++c) west = row[c] = UnZigZag(row[c]) + west;
      continue;
    }
    const uint32_t* up = row - width;
    row[0] = UnZigZag(row[0]) + up[0];
    for (size_t c = 1; c < len; ++c) row[c] = UnZigZag(row[c]) + up[c] - up[c - 1] + row[c - 1];
  }
  for (size_t i = 0; i < n; ++i) cells[i] = FloatOfKey(k[i]);
}

// Appends a Blosc frame (byte shuffle, typesize 4, zstd) of `nbytes` at `src`.
void AppendBlosc(const void* src, size_t nbytes, int level, std::vector<uint8_t>* out) {
  const size_t at = out->size();
  out->resize(at + nbytes + BLOSC_MAX_OVERHEAD);
  const int written =
      blosc_compress_ctx(level, BLOSC_SHUFFLE, sizeof(float), nbytes, src, out->data() + at,
                         nbytes + BLOSC_MAX_OVERHEAD, BLOSC_ZSTD_COMPNAME, 0, 1);
  // With a destination of nbytes + BLOSC_MAX_OVERHEAD Blosc always succeeds (blosc.h).
  out->resize(at + static_cast<size_t>(written));
}

// Decompresses the Blosc frame `frame` into `out` (exactly out.size_bytes() bytes).
Status ReadBlosc(std::span<const uint8_t> frame, std::span<float> out) {
  size_t nbytes = 0;
  if (frame.size() < BLOSC_MIN_HEADER_LENGTH ||
      blosc_cbuffer_validate(frame.data(), frame.size(), &nbytes) != 0)
    return Status::Corruption("block is not a valid Blosc frame");
  if (nbytes != out.size_bytes())
    return Status::Corruption("block holds " + std::to_string(nbytes) + " bytes, expected " +
                              std::to_string(out.size_bytes()));
  const int got = blosc_decompress_ctx(frame.data(), out.data(), out.size_bytes(), 1);
  if (got < 0 || static_cast<size_t>(got) != out.size_bytes())
    return Status::Corruption("block does not decompress (Blosc error " + std::to_string(got) +
                              ")");
  return Status::Ok();
}

Status DecodeShuffled(std::span<const uint8_t> data, std::span<float> out) {
  if (data.size() < kCrcBytes)
    return Status::Corruption("block of " + std::to_string(data.size()) + " bytes is too short");
  const size_t frame = data.size() - kCrcBytes;
  TB_RETURN_IF_ERROR(ReadBlosc(data.first(frame), out));
  if (ReadLe32(data.data() + frame) !=
      Crc32(reinterpret_cast<const uint8_t*>(out.data()), out.size_bytes()))
    return Status::Corruption("block fails its checksum");
  return Status::Ok();
}

Status DecodePlanar(std::span<const uint8_t> data, std::span<float> out) {
  if (data.size() < kWidthBytes + kCrcBytes)
    return Status::Corruption("block of " + std::to_string(data.size()) + " bytes is too short");
  const size_t body = data.size() - kCrcBytes;
  if (ReadLe32(data.data() + body) != Crc32(data.data(), body))
    return Status::Corruption("block fails its checksum");
  const uint32_t width = ReadLe32(data.data());
  if (width == 0) return Status::Corruption("block has rows of 0 cells");
  TB_RETURN_IF_ERROR(ReadBlosc(data.subspan(kWidthBytes, body - kWidthBytes), out));
  UndoPlanar(out, width);
  return Status::Ok();
}

}  // namespace

std::vector<uint8_t> EncodeBlock(std::span<const float> cells, int64_t row_width,
                                 BlockCodec codec) {
  std::vector<uint8_t> out;
  if (codec == BlockCodec::kBloscZstd) {
    AppendBlosc(cells.data(), cells.size_bytes(), kShuffleLevel, &out);
    AppendLe32(Crc32(reinterpret_cast<const uint8_t*>(cells.data()), cells.size_bytes()), &out);
    return out;
  }
  const size_t width = static_cast<size_t>(std::max<int64_t>(row_width, 1));
  AppendLe32(static_cast<uint32_t>(width), &out);
  const std::vector<uint32_t> residuals = PlanarResiduals(cells, width);
  AppendBlosc(residuals.data(), residuals.size() * sizeof(uint32_t), kPlanarLevel, &out);
  AppendLe32(Crc32(out.data(), out.size()), &out);
  return out;
}

Status DecodeBlockInto(int codec, std::span<const uint8_t> data, std::span<float> out) {
  switch (codec) {
    case static_cast<int>(BlockCodec::kBloscZstd):
      return DecodeShuffled(data, out);
    case static_cast<int>(BlockCodec::kPlanarBloscZstd):
      return DecodePlanar(data, out);
    default:
      return Status::InvalidArgument("unknown block codec " + std::to_string(codec));
  }
}

Result<std::vector<float>> DecodeBlock(int codec, std::span<const uint8_t> data, size_t count) {
  std::vector<float> cells(count);
  TB_RETURN_IF_ERROR(DecodeBlockInto(codec, data, cells));
  return cells;
}

}  // namespace tinbase
