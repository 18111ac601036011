// ContourLines: the lines where a TIN crosses levels base + k * interval, joined into polylines.
//
// In each triangle the plane crosses a level along one straight segment between two edges. A
// vertex exactly on the level counts as above it, so each triangle has zero or two crossed edges
// and no segment runs along an edge. An edge's crossing is computed from its lower-indexed
// vertex whichever triangle asks, so the two triangles that share it get the same point bit for
// bit, and segments are joined by edge, not by comparing coordinates. Segments are directed with
// higher ground on the right, which makes each crossing the end of at most one segment and the
// start of at most one, so polylines are walked without ambiguity: open ones from the boundary
// of the visible part, then closed rings. Thread-safety: pure function.
#pragma once

#include <vector>

#include "core/base/status.h"
#include "core/geometry/predicates.h"
#include "core/tin/tin.h"

namespace tinbase {

struct ContourOptions {
  double interval = 0;       // > 0
  double base = 0;           // levels are base + k * interval, k any integer
  bool visible_only = true;  // trace through visible triangles only
};

struct ContourLine {
  double level = 0;
  std::vector<Point2> points;  // >= 2 distinct points; higher ground on the right
  bool closed = false;         // the last point joins the first (not repeated)
};

// The contour lines of `tin`, by level then in the order they are found. InvalidArgument when
// the interval is not a finite positive number, the base is not finite, or the surface spans
// more than 100000 levels (naming the count); InvalidArgument too when no line results (no
// triangle, or no level crosses one), naming the surface's z range.
Result<std::vector<ContourLine>> TraceContours(const Tin& tin, const ContourOptions& options);

}  // namespace tinbase
