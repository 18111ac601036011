// DEM from contour lines (paper 000, the Singapore way): the contours' vertices become the
// vertices of a constrained Delaunay triangulation whose constrained edges are the contour
// segments, flat triangles are repaired with Steiner points, and the TIN is sampled at cell
// centres into a grid.
//
// Flat triangles (all three vertices on one level) appear wherever a contour bends back on
// itself (the nose of a ridge or a valley) or encloses a summit: the triangulation then joins the
// contour to itself and the DEM gets a terrace there. Each round, every flat triangle gets one
// Steiner point: the midpoint m of its longest unconstrained edge (its centroid when all three
// edges are contour segments). Its z is interpolated between the triangle's level L and the
// nearest other level L' found by walking from the triangle across unconstrained edges (that is,
// without crossing a contour): z = L + (L' - L) * d1 / (d1 + d2), with d1 the distance from m to
// the edge's ends (on contour L) and d2 the distance from m to that vertex at L'. A flat region
// closed off by contour L alone (a summit or a pit) has no such vertex; then L' is the level on
// the other side of the contour, mirrored: z = L + (L - L') / 2, half an interval beyond L, the
// unbiased guess for a top known only to lie between L and L + interval. (A walk visits at most
// 4096 flat triangles; a larger flat region is repaired from its edges inward over several
// rounds, and the mirror rule applies only to a region walked to its end.) The Steiner point is
// strictly between two levels, so it makes no new flat triangle at its own level; rounds repeat
// until none is left (at most kMaxSteinerRounds). Thread-safety: pure functions.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/predicates.h"
#include "core/raster/grid.h"
#include "core/tin/tin.h"

namespace tinbase {

struct ContourLine {
  std::string label;           // "contours.gpkg feature 12", names the line in messages
  double level = 0;            // elevation of every point
  std::vector<Point2> points;  // at least 2, finite
};

struct ContourDemReport {
  int64_t lines = 0;
  int64_t contour_vertices = 0;  // distinct contour vertices in the triangulation
  int64_t steiner_points = 0;
  int64_t rounds = 0;                // Steiner rounds run
  int64_t flat_triangles_found = 0;  // before repair
  int64_t flat_triangles_left = 0;   // after repair (0 unless a single level stands alone)
  int64_t triangles = 0;
};

inline constexpr int kMaxSteinerRounds = 24;

// OK when no two contours cross or touch. Lines of different levels may not share any point;
// lines of one level may touch (share a vertex, or one's vertex lie on the other's segment) but
// not cross, and a line may not cross itself. InvalidArgument naming both lines, their levels
// and the point: "c.gpkg feature 3 (level 1500) and c.gpkg feature 9 (level 1550) cross at
// (x, y)". REQUIRES: finite coordinates. O(n) buckets, O(n log n) typical.
Status CheckContoursDoNotCross(const std::vector<ContourLine>& lines);

// The contour TIN after Steiner repair: contour vertices (kind kUser, z the level) and Steiner
// points (kSteiner), contour segments as Tin::constraints, CCW, neighbours linked. Errors as
// CheckContoursDoNotCross; InvalidArgument when there are no lines, a line has fewer than 2
// points or a non-finite coordinate or level, or all points are collinear.
Result<Tin> BuildContourTin(const std::vector<ContourLine>& lines,
                            ContourDemReport* report = nullptr);

// The geometry of a grid of square `cell` cells covering [min, max] with edges on multiples of
// `cell` (so DEMs made at one cell size line up). REQUIRES: cell > 0, min <= max.
GridGeometry SnappedGridGeometry(double min_x, double min_y, double max_x, double max_y,
                                 double cell);

// BuildContourTin, sampled (barycentric) at the centres of SnappedGridGeometry(bounding box of
// the lines, cell); NaN outside the triangulation (the contours' convex hull). crs_wkt is left
// empty for the caller. Errors as BuildContourTin; InvalidArgument for a cell size that is not
// positive and finite or that would make more than 2^31 cells.
Result<Grid> DemFromContours(const std::vector<ContourLine>& lines, double cell,
                             ContourDemReport* report = nullptr);

}  // namespace tinbase
