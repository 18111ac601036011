// PlanRegion: an area of the plan (the union of polygons) cut into triangles, so that measures
// can clip convex pieces against it (core/measure/plan_overlay.h).
//
// The rings become the constrained edges of a CGAL triangulation (core/geometry/cdt.h); the
// triangles whose centroid lies inside the union are kept. Since every ring edge is an edge of
// the triangulation, those triangles tile the union exactly, holes left out.
// Thread-safety: immutable after construction.
#pragma once

#include <array>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/polygon.h"

namespace tinbase {

class PlanRegion {
 public:
  // The union of `polygons` (valid rings, MakeValidPolygon). InvalidArgument when there are no
  // polygons or their union has no area.
  static Result<PlanRegion> FromPolygons(const std::vector<Polygon>& polygons);

  // Counter-clockwise triangles tiling the region.
  const std::vector<std::array<Point2, 3>>& triangles() const { return triangles_; }
  double Area() const;

 private:
  std::vector<std::array<Point2, 3>> triangles_;
};

}  // namespace tinbase
