// Tile bounds: see tile_bounds.h.
#include "core/tiles/tile_bounds.h"

#include <GeographicLib/Geocentric.hpp>
#include <algorithm>
#include <cmath>

namespace tinbase {

namespace {

double Dot(const Ecef& a, const Ecef& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double Norm(const Ecef& a) { return std::sqrt(Dot(a, a)); }
Ecef Cross(const Ecef& a, const Ecef& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

Ecef ToScaledSpace(const Ecef& p) {
  const auto& wgs84 = GeographicLib::Geocentric::WGS84();
  const double a = wgs84.EquatorialRadius();
  const double b = a * (1 - wgs84.Flattening());
  return {p[0] / a, p[1] / a, p[2] / b};
}

// How far along `direction` (a unit vector in scaled space) the occlusion point must lie for
// `position` to be hidden whenever it is: the tangent-cone construction of Cesium's
// EllipsoidalOccluder.
double OcclusionMagnitude(const Ecef& position, const Ecef& direction) {
  const Ecef scaled = ToScaledSpace(position);
  double magnitude_squared = Dot(scaled, scaled);
  double magnitude = std::sqrt(magnitude_squared);
  const Ecef unit = {scaled[0] / magnitude, scaled[1] / magnitude, scaled[2] / magnitude};
  // Points below the ellipsoid are treated as on it.
  magnitude_squared = std::max(1.0, magnitude_squared);
  magnitude = std::max(1.0, magnitude);
  const double cos_alpha = Dot(unit, direction);
  const double sin_alpha = Norm(Cross(unit, direction));
  const double cos_beta = 1.0 / magnitude;
  const double sin_beta = std::sqrt(magnitude_squared - 1.0) * cos_beta;
  return 1.0 / (cos_alpha * cos_beta - sin_alpha * sin_beta);
}

}  // namespace

Ecef ToEcef(double lon, double lat, double height) {
  Ecef p{};
  GeographicLib::Geocentric::WGS84().Forward(lat, lon, height, p[0], p[1], p[2]);
  return p;
}

void SetTileBounds(const std::vector<Ecef>& positions, QuantizedMeshHeader& header) {
  Ecef lo = positions.front(), hi = positions.front();
  for (const Ecef& p : positions)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  const Ecef center = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  double radius = 0;
  for (const Ecef& p : positions)
    radius = std::max(radius, Norm({p[0] - center[0], p[1] - center[1], p[2] - center[2]}));
  header.center_x = center[0];
  header.center_y = center[1];
  header.center_z = center[2];
  header.sphere_x = center[0];
  header.sphere_y = center[1];
  header.sphere_z = center[2];
  header.sphere_radius = radius;

  Ecef direction = ToScaledSpace(center);
  const double length = Norm(direction);
  for (double& c : direction) c /= length;
  double magnitude = 0;
  for (const Ecef& p : positions) {
    const double m = OcclusionMagnitude(p, direction);
    // A vertex that can never be hidden (the cone opens past 90 degrees) makes the tile
    // uncullable: Cesium then ignores the point, so any finite value is safe; keep the largest
    // finite one.
    if (std::isfinite(m) && m > 0) magnitude = std::max(magnitude, m);
  }
  header.horizon_x = direction[0] * magnitude;
  header.horizon_y = direction[1] * magnitude;
  header.horizon_z = direction[2] * magnitude;
}

}  // namespace tinbase
