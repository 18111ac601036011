// PlanOverlay: the plan cut into convex pieces on which every surface involved is one plane.
//
// Measures between two surfaces, or inside a polygon, need the common refinement of two
// triangulations (and a region's triangles): each visible triangle of `a` is intersected with
// the visible triangles of `b` whose boxes meet its own (a uniform grid of boxes finds them),
// then with the region's triangles, by convex clipping (Sutherland-Hodgman against each
// counter-clockwise edge). On a piece both surfaces are linear, so integrals over it are exact
// (core/measure/level_split.h). Intersection points are rounded; the pieces of one triangle of
// `a` tile it up to that rounding (slivers along shared edges have no area).
// Coordinates stay relative to a piece's origin (corner 0 of its triangle of `a`), because
// differences of whole eastings would cost the clipping its low digits. Thread-safety: pure.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/geometry/predicates.h"
#include "core/measure/plan_region.h"
#include "core/tin/tin.h"

namespace tinbase {

struct OverlayPiece {
  Point2 origin;             // corner 0 of triangle a's plan position
  std::vector<Point2> ring;  // convex, counter-clockwise, relative to origin, >= 3 points
  uint32_t a = 0;            // triangle of `a`
  int32_t b = -1;            // triangle of `b`, or -1 without `b`
};

using OverlayVisitor = std::function<void(const OverlayPiece&)>;

// Calls `visit` for each piece of (visible triangles of a) ∩ (visible triangles of b, when b is
// not null) ∩ (region, when not null), in triangle order of a. Pieces have positive area.
void ForEachOverlayPiece(const Tin& a, const Tin* b, const PlanRegion* region,
                         const OverlayVisitor& visit);

// z of triangle t of `tin` (its plane) at plan position origin + r. REQUIRES: t is not
// degenerate in plan.
double PlaneZ(const Tin& tin, uint32_t t, const Point2& origin, const Point2& r);

}  // namespace tinbase
