// Exact plan-view tests of a point or a segment against one triangle, and of a triangle's
// circumcircle against many points. Used by the update engine to walk a segment across a mesh
// and to grow its conflict region (db/edit/conflict_region.h); they decide topology, so every
// sign comes from the exact predicates (core/geometry/predicates.h). Stateless; thread-safe.
#pragma once

#include <array>
#include <vector>

#include "core/geometry/predicates.h"

namespace tinbase {

using TriangleCorners = std::array<Point2, 3>;

// True when the closed segment pq and the closed triangle abc share a point.
// REQUIRES: a, b, c counter-clockwise.
bool SegmentMeetsTriangle(const Point2& p, const Point2& q, const Point2& a, const Point2& b,
                          const Point2& c);

// True when `p` lies inside the triangle `c`, off its edges. REQUIRES: c counter-clockwise.
bool StrictlyInside(const TriangleCorners& c, const Point2& p);

// True when some point of `sorted_by_x` (sorted by x) lies strictly inside the circumcircle of
// `c`. REQUIRES: c counter-clockwise.
bool CircleHoldsAny(const TriangleCorners& c, const std::vector<Point2>& sorted_by_x);

}  // namespace tinbase
