// BlockCodec: how one DEM block's float32 cells become the bytes of a `dem_blocks.data` BLOB.
//
// A block is `count` float32 cells, row-major, NaN = nodata. The codec id is stored beside the
// bytes (`dem_blocks.codec`) so old blocks stay readable when a new codec is added; EncodeBlock
// writes kPlanarBloscZstd, DecodeBlock reads both (layouts in docs/format.md).
//   kBloscZstd (1): Blosc (byte shuffle, zstd) of the float bits, then a CRC-32 of the cells.
//   kPlanarBloscZstd (2): every cell predicted from its west, north and north-west neighbours
//     (the plane through them) on order-preserving integer keys of the float bits, the residuals
//     zigzag-coded, then Blosc (byte shuffle, zstd) and a CRC-32 of the stored bytes. Terrain is
//     locally planar, so residuals are small and the high bytes mostly zero: 10-15 % smaller
//     than GDAL's floating-point predictor with zstd, still lossless bit for bit.
// Blosc frames carry no checksum of their own, so the CRC is what turns a flipped bit into a
// Corruption error instead of a silently wrong elevation.
// Thread-safety: free functions without shared state (Blosc's context API), safe from any thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/base/status.h"

namespace tinbase {

enum class BlockCodec : int { kBloscZstd = 1, kPlanarBloscZstd = 2 };

// The bytes of `cells` (rows of `row_width` cells; the last row may be short) under `codec`.
// Never fails. REQUIRES: row_width >= 1.
std::vector<uint8_t> EncodeBlock(std::span<const float> cells, int64_t row_width,
                                 BlockCodec codec = BlockCodec::kPlanarBloscZstd);

// Decodes `data` (stored with codec id `codec`) into exactly `count` cells. Corruption when the
// bytes are not a valid frame, hold another number of cells, or fail the checksum; InvalidArgument
// for an unknown codec id.
Result<std::vector<float>> DecodeBlock(int codec, std::span<const uint8_t> data, size_t count);
// The same into `out`, which must hold `count` cells (no allocation: the window-read path).
Status DecodeBlockInto(int codec, std::span<const uint8_t> data, std::span<float> out);

}  // namespace tinbase
