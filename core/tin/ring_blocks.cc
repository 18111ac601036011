#include "core/tin/ring_blocks.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace tinbase {

namespace {

// Liang-Barsky: does segment ab meet the closed box [x0, x1] x [y0, y1]?
bool SegmentMeetsBox(const Point2& a, const Point2& b, double x0, double y0, double x1, double y1) {
  double t0 = 0, t1 = 1;
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {a.x - x0, x1 - a.x, a.y - y0, y1 - a.y};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0) {
      if (q[k] < 0) return false;  // parallel to this side and outside it
      continue;
    }
    const double t = q[k] / p[k];
    if (p[k] < 0)
      t0 = std::max(t0, t);
    else
      t1 = std::min(t1, t);
    if (t0 > t1) return false;
  }
  return true;
}

}  // namespace

RingBlocks::RingBlocks(const BlockGrid& grid, const BlockWindow& window)
    : grid_(grid), window_(window) {
  assert(!window.empty());
  near_.assign(static_cast<size_t>(window.columns() * window.rows()), 0);
}

void RingBlocks::AddRings(const std::vector<Polygon>& polygons) {
  const auto add_ring = [this](const Ring& ring) {
    for (size_t i = 0; i < ring.size(); ++i) AddSegment(ring[i], ring[(i + 1) % ring.size()]);
  };
  for (const Polygon& p : polygons) {
    add_ring(p.shell);
    for (const Ring& hole : p.holes) add_ring(hole);
  }
}

void RingBlocks::AddBlocks(const std::vector<int64_t>& packed) {
  for (int64_t id : packed) {
    const int64_t by = BlockGrid::RowOfPacked(id), bx = BlockGrid::ColumnOfPacked(id);
    if (window_.Contains(bx, by)) near_[Index(bx, by)] = 1;
  }
}

std::vector<int64_t> BlocksNearRings(const BlockGrid& grid, const std::vector<Polygon>& polygons) {
  double min_x = INFINITY, min_y = INFINITY, max_x = -INFINITY, max_y = -INFINITY;
  for (const Polygon& p : polygons) {
    for (const Point2& q : p.shell) {
      min_x = std::min(min_x, q.x), max_x = std::max(max_x, q.x);
      min_y = std::min(min_y, q.y), max_y = std::max(max_y, q.y);
    }
  }
  if (!(min_x <= max_x && min_y <= max_y)) return {};  // no shell point (holes lie inside it)
  // Every block a segment can mark: its box grown by the margin AddSegment grows blocks by.
  const double m = RingBlocks::kMargin * grid.size;
  const BlockWindow window{grid.ColumnOf(min_x - m), grid.RowOf(min_y - m),
                           grid.ColumnOf(max_x + m), grid.RowOf(max_y + m)};
  RingBlocks near(grid, window);
  near.AddRings(polygons);
  std::vector<int64_t> packed;
  for (int64_t by = window.by0; by <= window.by1; ++by)
    for (int64_t bx = window.bx0; bx <= window.bx1; ++bx)
      if (near.Near(bx, by)) packed.push_back(BlockGrid::Pack(bx, by));
  return packed;
}

void RingBlocks::AddSegment(const Point2& a, const Point2& b) {
  const double m = kMargin * grid_.size;
  const auto column = [&](double x) {
    return static_cast<int64_t>(std::floor((x - grid_.origin_x) / grid_.size));
  };
  const auto row = [&](double y) {
    return static_cast<int64_t>(std::floor((y - grid_.origin_y) / grid_.size));
  };
  const int64_t left = column(std::min(a.x, b.x) - m), right = column(std::max(a.x, b.x) + m);
  const int64_t bottom = row(std::min(a.y, b.y) - m), top = row(std::max(a.y, b.y) + m);
  // Ring segments are mostly shorter than a block: their box is the answer. Longer ones test
  // each block of their box, so a long diagonal does not mark a whole square of blocks. Judged
  // on the whole box, not its part in the window, so every window marks the same blocks.
  const bool small = right - left <= 1 && top - bottom <= 1;
  const int64_t bx0 = std::max(window_.bx0, left), bx1 = std::min(window_.bx1, right);
  const int64_t by0 = std::max(window_.by0, bottom), by1 = std::min(window_.by1, top);
  for (int64_t by = by0; by <= by1; ++by) {
    for (int64_t bx = bx0; bx <= bx1; ++bx) {
      uint8_t& near = near_[Index(bx, by)];
      if (near) continue;
      const double x0 = grid_.origin_x + static_cast<double>(bx) * grid_.size - m;
      const double y0 = grid_.origin_y + static_cast<double>(by) * grid_.size - m;
      if (small || SegmentMeetsBox(a, b, x0, y0, x0 + grid_.size + 2 * m, y0 + grid_.size + 2 * m))
        near = 1;
    }
  }
}

}  // namespace tinbase
