// Fuzzes DecodeBlock (core/raster/block_codec.h), which reads DEM blocks from a store file that
// may be damaged: any bytes decode to exactly the cells asked for or to an error, never a crash
// or a read out of bounds. The first byte picks the codec, the second the cell count.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "core/raster/block_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const int codec = data[0] % 4;
  const size_t count = size_t{data[1]} * 64;
  auto cells = tinbase::DecodeBlock(codec, std::span<const uint8_t>(data + 2, size - 2), count);
  if (cells.ok() && cells->size() != count) std::abort();
  return 0;
}
