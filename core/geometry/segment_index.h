// SegmentIndex: answers "does this point lie exactly on one of these segments" through a coarse
// bucket grid of about sqrt(n) x sqrt(n) cells; the answer comes from the exact orientation
// test. The update engine asks it whether a refinement point would split its conflict region's
// outline (db/edit/local_patch.cc). Immutable after Build; reads are thread-safe.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/geometry/predicates.h"

namespace tinbase {

class SegmentIndex {
 public:
  // Replaces the indexed segments by `segments` (closed, in plan view).
  void Build(std::vector<std::pair<Point2, Point2>> segments);

  // True when `p` lies on one of the segments, ends included (exact).
  bool OnAny(const Point2& p) const;

 private:
  int64_t Col(double x) const { return Index(x, min_x_, max_x_); }
  int64_t Row(double y) const { return Index(y, min_y_, max_y_); }
  int64_t Index(double v, double lo, double hi) const;

  std::vector<std::pair<Point2, Point2>> segments_;
  double min_x_ = 0, min_y_ = 0, max_x_ = -1, max_y_ = -1;  // empty until Build
  int64_t side_ = 1;
  std::vector<std::vector<uint32_t>> cells_;
};

}  // namespace tinbase
