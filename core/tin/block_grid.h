// BlockGrid: the spatial buckets that index a surface's triangles by centroid.
//
// Each stored triangle carries the block of its centroid, so point location can jump to a
// triangle near the query point with one indexed lookup and walk from there (docs/design.md,
// "Point location"). Blocks are squares of `size` map units from `origin`; a block id packs
// (bx, by) so it fits one indexed integer column. Plain value type.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace tinbase {

struct BlockGrid {
  static constexpr int64_t kStride = int64_t{1} << 24;  // bx, by in [0, kStride)

  double origin_x = 0;
  double origin_y = 0;
  double size = 1;  // > 0

  int64_t ColumnOf(double x) const { return Clamp(std::floor((x - origin_x) / size)); }
  int64_t RowOf(double y) const { return Clamp(std::floor((y - origin_y) / size)); }
  static int64_t Pack(int64_t bx, int64_t by) { return by * kStride + bx; }
  // bx and by of a packed id.
  static int64_t ColumnOfPacked(int64_t packed) { return packed % kStride; }
  static int64_t RowOfPacked(int64_t packed) { return packed / kStride; }
  int64_t BlockOf(double x, double y) const { return Pack(ColumnOf(x), RowOf(y)); }

  static constexpr int64_t kDefaultPerBlock = 32;

  // A grid whose blocks hold about `per_block` of `count` items spread over the box.
  static BlockGrid For(double min_x, double min_y, double max_x, double max_y, int64_t count,
                       int64_t per_block = kDefaultPerBlock) {
    const double area = std::max((max_x - min_x) * (max_y - min_y), 1e-12);
    const double blocks = std::max<double>(1.0, static_cast<double>(count) / per_block);
    double size = std::sqrt(area / blocks);
    const double span = std::max(max_x - min_x, max_y - min_y);
    size = std::max(size, span / static_cast<double>(kStride - 1));
    if (!(size > 0)) size = 1;
    return BlockGrid{min_x, min_y, size};
  }

 private:
  static int64_t Clamp(double v) {
    return static_cast<int64_t>(std::clamp(v, 0.0, static_cast<double>(kStride - 1)));
  }
};

}  // namespace tinbase
