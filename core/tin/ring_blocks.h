// RingBlocks: which centroid blocks (core/tin/block_grid.h) of a window of blocks the rings of
// some polygons come near.
//
// Painting decides "inside" per triangle centroid (core/tin/feature_paint.h). In a block that no
// ring of any feature comes near, each feature is inside for every centroid of the block or for
// none, so all the triangles whose centroid block it is take one paint, found at any point of the
// block: the update engine repaints such blocks with one statement instead of reading and
// painting their triangles one by one (a fill over most of a surface repaints ~1e5 triangles).
//
// "Near" is conservative: a block is enlarged by kMargin of its size on every side before the
// segment test, which is done in doubles. The enlargement is far more than the round-off in a
// stored triangle's centroid block (CentroidBlock) or in the test itself, so a ring that meets a
// block always marks it; a false "near" only sends the block down the slower path.
// Plain value type; not thread-safe while being filled.
#pragma once

#include <cstdint>
#include <vector>

#include "core/geometry/polygon.h"
#include "core/tin/block_grid.h"

namespace tinbase {

// The blocks (bx0..bx1) x (by0..by1) of a grid, inclusive.
struct BlockWindow {
  int64_t bx0 = 0, by0 = 0, bx1 = -1, by1 = -1;

  int64_t columns() const { return bx1 - bx0 + 1; }
  int64_t rows() const { return by1 - by0 + 1; }
  bool empty() const { return bx1 < bx0 || by1 < by0; }
  bool Contains(int64_t bx, int64_t by) const {
    return bx >= bx0 && bx <= bx1 && by >= by0 && by <= by1;
  }
};

class RingBlocks {
 public:
  static constexpr double kMargin = 1e-3;  // of the block size

  // REQUIRES: `window` is not empty and spans fewer than 2^31 blocks.
  RingBlocks(const BlockGrid& grid, const BlockWindow& window);

  // Marks the blocks of the window every ring (shells and holes) of `polygons` comes near.
  void AddRings(const std::vector<Polygon>& polygons);
  // Marks those of `packed` (BlockGrid::Pack ids, as BlocksNearRings gives them) that lie in the
  // window: the same blocks AddRings marks for the same rings, without testing a segment.
  void AddBlocks(const std::vector<int64_t>& packed);

  // True when a ring added so far comes near block (bx, by). REQUIRES: window.Contains(bx, by).
  bool Near(int64_t bx, int64_t by) const { return near_[Index(bx, by)] != 0; }

  // The centre of block (bx, by), the point its paint is taken at.
  Point2 Centre(int64_t bx, int64_t by) const {
    return {grid_.origin_x + (static_cast<double>(bx) + 0.5) * grid_.size,
            grid_.origin_y + (static_cast<double>(by) + 0.5) * grid_.size};
  }

 private:
  size_t Index(int64_t bx, int64_t by) const {
    return static_cast<size_t>((by - window_.by0) * window_.columns() + (bx - window_.bx0));
  }
  void AddSegment(const Point2& a, const Point2& b);

  BlockGrid grid_;
  BlockWindow window_;
  std::vector<uint8_t> near_;
};

// Every block of `grid` the rings of `polygons` come near, packed (BlockGrid::Pack) and sorted:
// what AddRings marks in any window, found once. The paint area of an edit marks the rings of
// every feature near it, and in a map whose features' boxes overlap (contour bands) testing the
// same rings' segments again in every edit was a tenth of a feature-by-feature load.
std::vector<int64_t> BlocksNearRings(const BlockGrid& grid, const std::vector<Polygon>& polygons);

}  // namespace tinbase
