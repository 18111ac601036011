// LineElevation: the z that 3D lines (features with z from the feature: LineString Z, contours)
// give the plan points on them, and the band around them where a surface's DEM tolerance yields
// to them (docs/design.md, "Soft lines and z from the feature").
//
// The z rule: a point on a 3D line takes the line's z, linear along the segment it lies on
// (vertices keep their own). Where 3D lines cross or touch, the line added last (the highest
// feature id) gives the point its z; the other line bends there. A 3D line's z also wins over a
// replace feature's level and over the DEM. "On" a line means within `near` of it in plan:
// the distance below which the update engine snaps points together (kSnapCells), so a computed
// crossing that round-off puts beside both segments still counts as on both.
// Thread-safety: immutable after construction; const methods may be called concurrently.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/geometry/polygon.h"

namespace tinbase {

// One 3D line: plan points and their z (same length, >= 2), of feature `feature`.
struct Line3 {
  int64_t feature = 0;
  std::vector<Point2> points;
  std::vector<double> z;
};

// The half-width, in DEM cells, of the band along a 3D line where the surface's DEM tolerance
// does not apply: the line's z may depart from the DEM's, and the surface has to step between
// them somewhere; within a cell of the line it may (both the refiner and `tinbase check` use it).
inline constexpr double kLineBandCells = 1.0;

class LineElevation {
 public:
  LineElevation() = default;
  // `lines` in any order; `near` > 0 (map units).
  LineElevation(std::vector<Line3> lines, double near);

  bool empty() const { return segments_.empty(); }
  // The z the lines give `p` (the highest feature id among the lines within `near` of p);
  // nullopt when no 3D line passes that close.
  std::optional<double> ZAt(const Point2& p) const;
  // Whether some 3D line passes within `distance` of `p`.
  bool Near(const Point2& p, double distance) const;

 private:
  struct Segment {
    Point2 a, b;
    double za = 0, zb = 0;
    int64_t feature = 0;
    double min_x = 0, min_y = 0, max_x = 0, max_y = 0;  // plan box
  };
  // Segments whose box, grown by `reach`, holds p: calls visit(segment) for each.
  template <typename Visit>
  void ForEachNear(const Point2& p, double reach, const Visit& visit) const;

  std::vector<Segment> segments_;  // sorted by min_x
  double max_width_ = 0;           // the widest segment box in x
  double near_ = 0;
};

}  // namespace tinbase
