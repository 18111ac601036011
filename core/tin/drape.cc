#include "core/tin/drape.h"

#include <cmath>
#include <string>

namespace tinbase {

namespace {

struct Drape {
  const DrapeElevationFn& elevation;
  const DrapeOptions& options;
  std::vector<TinVertex> out;

  // Appends the points strictly between a and b that the tolerance asks for, in order.
  // Depth-limited as a guard: 2^30 pieces is beyond any real segment at min_spacing.
  Status Refine(const TinVertex& a, const TinVertex& b, size_t vertex, int depth) {
    const double length = std::hypot(b.x - a.x, b.y - a.y);
    if (length <= 2 * options.min_spacing || depth > 30) return Status::Ok();
    TinVertex mid{(a.x + b.x) / 2, (a.y + b.y) / 2, 0, VertexKind::kRing};
    auto z = elevation(mid.x, mid.y);
    if (!z.ok()) return z.status().WithContext("vertex " + std::to_string(vertex));
    mid.z = *z;
    if (!std::isfinite(mid.z))
      return Status::InvalidArgument("vertex " + std::to_string(vertex) + ": no elevation at " +
                                     FormatPoint({mid.x, mid.y}) +
                                     " on the way to the next vertex");
    if (std::abs(mid.z - (a.z + b.z) / 2) <= options.tolerance) return Status::Ok();
    TB_RETURN_IF_ERROR(Refine(a, mid, vertex, depth + 1));
    out.push_back(mid);
    return Refine(mid, b, vertex, depth + 1);
  }
};

}  // namespace

Result<std::vector<TinVertex>> DrapePolyline(const std::vector<Point2>& points,
                                             const DrapeElevationFn& elevation,
                                             const DrapeOptions& options) {
  if (!(options.tolerance > 0) || !(options.min_spacing > 0))
    return Status::InvalidArgument("drape tolerance and spacing must be positive");
  if (points.size() < 2) return Status::InvalidArgument("a polyline needs at least 2 vertices");
  std::vector<TinVertex> lifted;
  for (size_t i = 0; i < points.size(); ++i) {
    auto read = elevation(points[i].x, points[i].y);
    if (!read.ok()) return read.status().WithContext("vertex " + std::to_string(i));
    const double z = *read;
    if (!std::isfinite(z))
      return Status::InvalidArgument("vertex " + std::to_string(i) + ": no elevation at " +
                                     FormatPoint(points[i]) + " (outside the DEM or on nodata)");
    lifted.push_back({points[i].x, points[i].y, z, VertexKind::kRing});
  }
  Drape drape{elevation, options, {}};
  const size_t segments = options.closed ? lifted.size() : lifted.size() - 1;
  for (size_t i = 0; i < lifted.size(); ++i) {
    drape.out.push_back(lifted[i]);
    if (i < segments)
      TB_RETURN_IF_ERROR(drape.Refine(lifted[i], lifted[(i + 1) % lifted.size()], i, 0));
  }
  return std::move(drape.out);
}

}  // namespace tinbase
