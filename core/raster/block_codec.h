// BlockCodec: how one DEM block's float32 cells become the bytes of a `dem_blocks.data` BLOB.
//
// A block is `count` float32 cells, row-major, NaN = nodata. The codec id is stored beside the
// bytes (`dem_blocks.codec`) so old blocks stay readable when a new codec is added. Layout of
// kBloscZstd (docs/format.md): one Blosc 1 frame (byte shuffle, zstd, typesize 4) of the cells as
// little-endian IEEE-754 float32, then a 4-byte little-endian CRC-32 (zlib polynomial) of those
// uncompressed bytes. Blosc frames carry no checksum of their own, so the CRC is what turns a
// flipped bit into a Corruption error instead of a silently wrong elevation.
// Thread-safety: free functions without shared state (Blosc's context API), safe from any thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/base/status.h"

namespace tinbase {

enum class BlockCodec : int { kBloscZstd = 1 };

// The bytes of `cells` under `codec`. Never fails for a valid codec.
std::vector<uint8_t> EncodeBlock(std::span<const float> cells,
                                 BlockCodec codec = BlockCodec::kBloscZstd);

// Decodes `data` (stored with codec id `codec`) into exactly `count` cells. Corruption when the
// bytes are not a valid frame, hold another number of cells, or fail the checksum; InvalidArgument
// for an unknown codec id.
Result<std::vector<float>> DecodeBlock(int codec, std::span<const uint8_t> data, size_t count);

}  // namespace tinbase
