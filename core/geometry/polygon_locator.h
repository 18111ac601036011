// PolygonLocator: answers "is this point inside these polygons?" many times over.
//
// Feature painting asks it once per triangle centroid or vertex, for 1e5 triangles against
// rings of thousands of vertices, so the edges are bucketed by horizontal bands: a point only
// tests the edges whose y-range meets its own band (the even-odd ray to the right can only
// cross those). Each test is exact (CGAL's orientation predicate on the input doubles), so a
// point is never inside two polygons that share an edge. The locator copies the edges it needs.
// Thread-safety: immutable after construction; Locate may be called from many threads.
#pragma once

#include <cstdint>
#include <vector>

#include "core/geometry/polygon.h"

namespace tinbase {

class PolygonLocator {
 public:
  // The union of `polygons` (each shell minus its holes); polygons may overlap.
  // REQUIRES: rings are simple (MakeValidPolygon), open.
  explicit PolygonLocator(const std::vector<Polygon>& polygons);

  // kBoundary when `p` lies on a ring of a polygon and inside no other polygon.
  PointInPolygon Locate(const Point2& p) const;

  bool empty() const { return edges_.empty(); }
  // The plan-view box of every ring (inverted, min above max, when there is none).
  Point2 min() const { return {min_x_, min_y_}; }
  Point2 max() const { return {max_x_, max_y_}; }

 private:
  struct Edge {
    Point2 a, b;
    uint32_t polygon;
  };
  int64_t BandOf(double y) const;

  std::vector<Edge> edges_;  // in polygon order, so each band's list is grouped by polygon
  double min_x_ = 0, min_y_ = 0, max_x_ = 0, max_y_ = 0;
  double band_height_ = 1;
  std::vector<uint32_t> band_begin_;  // CSR: edges of band k are band_edges_[begin[k], begin[k+1])
  std::vector<uint32_t> band_edges_;
};

}  // namespace tinbase
