// Edge collapse: a TIN simplified to a face budget (paper 002), with CGAL's
// Surface_mesh_simplification.
//
// The TIN's 3D vertices and triangles become a halfedge mesh; edges are collapsed cheapest first
// until at most `faces` triangles remain. Two cost/placement strategies:
//   - kGarlandHeckbert: CGAL's plane-quadric policies (Garland and Heckbert 1997): the cost of a
//     collapse is the squared distance of the new vertex to the planes of the triangles merged
//     into it, and the new vertex goes where that error is least (a constructed point, kind
//     kSteiner). CGAL's policies need Eigen; a build without it (no TINBASE_HAVE_EIGEN) uses
//     CGAL's Lindstrom-Turk policies instead, also quadric-based (memoryless: volume and
//     boundary preservation, then shape), and CollapseStrategyName still says "quadric".
//   - kShortFlatLowDegree: the paper's criteria, cheapest first: short edges, small height
//     difference, low degree of the two vertices. The new vertex is one of the two endpoints, so
//     every vertex stays a DEM sample.
// Two rules hold for every collapse, whatever the strategy, so the result is a valid plan-view
// tiling of the same domain (a "free" surface, docs/design.md, "Data model"):
//   - no fold-over: a placement is refused when any triangle around it would turn clockwise or
//     collinear in plan view (exact orientation, core/geometry/predicates.h); then the new fan
//     covers exactly the old one. Between two free vertices the placement falls back to an
//     endpoint (the nearer to the strategy's point first) when the strategy's point folds;
//     otherwise the collapse is refused.
//   - the outline is kept: boundary vertices stay where they are, except that a boundary vertex
//     lying on the straight line between its two boundary neighbours may merge into one of them
//     along the boundary (the outline's shape does not change). Corners of the outline and
//     vertices of constrained edges are never removed, constrained edges never collapsed (CGAL's
//     edge constraint map). A rectangle can thus shrink to its four corners: two triangles.
// When no allowed collapse is left before the budget is reached, the result has more faces than
// asked for; the report says how many. Thread-safety: pure function.
#pragma once

#include <cstdint>
#include <string>

#include "core/base/status.h"
#include "core/raster/grid.h"
#include "core/tin/tin.h"

namespace tinbase {

enum class CollapseStrategy { kGarlandHeckbert, kShortFlatLowDegree };

// "quadric" / "paper"; ParseCollapseStrategy is false for any other name.
const char* CollapseStrategyName(CollapseStrategy strategy);
bool ParseCollapseStrategy(const std::string& name, CollapseStrategy* strategy);

struct CollapseOptions {
  int64_t faces = 0;  // face budget; >= 2
  CollapseStrategy strategy = CollapseStrategy::kGarlandHeckbert;
};

struct CollapseReport {
  int64_t faces_in = 0;
  int64_t faces_out = 0;
  int64_t vertices_in = 0;
  int64_t vertices_out = 0;
  int64_t foldovers_refused = 0;  // collapses the plan-view rule refused (each time tried)
  bool budget_met = false;        // faces_out <= options.faces
  // Vertical error against the reference grid, when one was given (else 0).
  double max_error = 0;
  double rms_error = 0;
  int64_t cells_compared = 0;
};

// The simplified TIN: vertices that survive keep their kind (constructed ones are kSteiner),
// triangles counter-clockwise in plan view with neighbours linked (LinkNeighbours), the input's
// constraints kept (renumbered), all triangles visible and untagged. `report`, when given, is
// filled; the error fields compare against `reference` at its valid cell centres when given.
// Errors (InvalidArgument): a budget below 2; an input with no triangle, a triangle that refers
// to a missing vertex or is not counter-clockwise in plan view, or triangles that do not form a
// manifold surface ("triangle t: ..."). REQUIRES: finite coordinates.
Result<Tin> CollapseToFaceBudget(const Tin& input, const CollapseOptions& options,
                                 CollapseReport* report = nullptr, const Grid* reference = nullptr);

}  // namespace tinbase
