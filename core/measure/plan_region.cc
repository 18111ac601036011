#include "core/measure/plan_region.h"

#include "core/geometry/cdt.h"
#include "core/geometry/polygon_locator.h"

namespace tinbase {

Result<PlanRegion> PlanRegion::FromPolygons(const std::vector<Polygon>& polygons) {
  if (polygons.empty()) return Status::InvalidArgument("no polygon to measure inside");
  std::vector<TinVertex> points;
  std::vector<std::pair<size_t, size_t>> edges;  // positions in `points`
  const auto add_ring = [&](const Ring& ring) {
    const size_t first = points.size();
    for (const Point2& p : ring) points.push_back({p.x, p.y, 0, VertexKind::kUser});
    for (size_t i = 0; i < ring.size(); ++i) {
      edges.emplace_back(first + i, first + (i + 1) % ring.size());
    }
  };
  for (const Polygon& polygon : polygons) {
    add_ring(polygon.shell);
    for (const Ring& hole : polygon.holes) add_ring(hole);
  }
  Cdt cdt;
  const std::vector<uint32_t> index = cdt.InsertVertices(points);
  for (const auto& [a, b] : edges) {
    if (index[a] != index[b]) cdt.InsertConstraint(index[a], index[b]);
  }
  // Overlapping polygons' rings may cross; the crossing vertices need some z, which no measure
  // reads.
  const Tin tin = cdt.ToTin([](double, double) { return 0.0; });
  const PolygonLocator inside(polygons);
  PlanRegion region;
  for (const TinTriangle& t : tin.triangles) {
    std::array<Point2, 3> corners;
    for (int i = 0; i < 3; ++i) corners[i] = {tin.vertices[t.v[i]].x, tin.vertices[t.v[i]].y};
    const Point2 centroid{(corners[0].x + corners[1].x + corners[2].x) / 3,
                          (corners[0].y + corners[1].y + corners[2].y) / 3};
    if (inside.Locate(centroid) == PointInPolygon::kInside) region.triangles_.push_back(corners);
  }
  if (region.triangles_.empty()) return Status::InvalidArgument("the polygons have no area");
  return region;
}

double PlanRegion::Area() const {
  double sum = 0;
  for (const auto& c : triangles_) {
    sum += 0.5 * ((c[1].x - c[0].x) * (c[2].y - c[0].y) - (c[1].y - c[0].y) * (c[2].x - c[0].x));
  }
  return sum;
}

}  // namespace tinbase
