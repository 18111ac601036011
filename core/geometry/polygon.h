// Polygon: a shell with holes in plan view, and the validation every polygon passes before it
// reaches a surface (docs/design.md, "Inserting a polygon", step 1).
//
// Rings are stored open (the closing vertex is not repeated), the shell counter-clockwise and
// holes clockwise. Validation works on rings as a reader found them (closed, possibly with
// repeated points) so that its messages name the vertex numbers the user sees in the file:
// "ring 0, vertex 7: ring crosses itself at (x, y)". Plain data and pure functions.
#pragma once

#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/predicates.h"

namespace tinbase {

// True when p and q are the same point: readers repeat vertices bit for bit, so exact.
inline bool SamePoint(const Point2& p, const Point2& q) { return p.x == q.x && p.y == q.y; }

using Ring = std::vector<Point2>;

struct Polygon {
  Ring shell;               // counter-clockwise, open
  std::vector<Ring> holes;  // clockwise, open
};

// Turns rings as read from a source (rings[0] the shell, the others its holes; each closed,
// i.e. its last vertex equal to its first) into a valid Polygon: the closing vertex and
// consecutive repeated points are dropped and the rings oriented. Returns InvalidArgument whose
// message starts with "ring r" (and ", vertex v" where one vertex is to blame), for: no rings, a
// ring not closed, a non-finite coordinate, fewer than 3 distinct points, a ring that crosses,
// touches or folds back on itself, two rings that cross or share an edge, a hole not inside the
// shell, a hole inside another hole, or rings whose contact points cut the interior apart.
// Vertex numbers are 0-based positions in the input ring. Rings may touch each other at single
// points as long as the interior stays connected (as OGC simple features allow); the accepted
// polygons are exactly those GEOS calls valid (checked by a property test).
Result<Polygon> MakeValidPolygon(const std::vector<Ring>& rings);

// One edge's part in the even-odd ray test (a ray from p towards +x): kOnEdge when p lies on
// segment ab, kCross when the ray crosses it (half-open in y, so a ray through a vertex counts
// once), else kMiss. Exact.
enum class EdgeRay { kMiss, kCross, kOnEdge };
EdgeRay RayTest(const Point2& a, const Point2& b, const Point2& p);

// Where p lies relative to one open ring, by the even-odd rule. Linear in the ring's size; use
// PolygonLocator for many queries.
enum class PointInPolygon { kOutside, kBoundary, kInside };
PointInPolygon LocateInRing(const Ring& ring, const Point2& p);

// Twice the signed area of an open ring: positive when counter-clockwise.
double SignedDoubleArea(const Ring& ring);

// "(x, y)" with the shortest text that reads back as the same doubles.
std::string FormatPoint(const Point2& p);

}  // namespace tinbase
