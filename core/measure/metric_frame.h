// MetricFrame: how a store's plan coordinates and heights become metres for measuring.
//
// Every measure (area, volume, slope) works on one triangle or one convex piece at a time, so a
// frame only has to map three corners into a local Cartesian frame in metres:
//  - projected (or no) CRS: plan coordinates times the CRS's linear unit, heights times the
//    vertical unit, shifted so corner 0 is the origin (differences of 6-7 digit eastings would
//    otherwise cost the products their low digits). Areas are then map-plane areas: the
//    projection's scale error is not removed (a UTM zone is within 0.04 % of true at its edge
//    and smaller near its centre).
//  - geographic CRS (x = longitude, y = latitude, degrees): each piece's plan positions go to
//    the plane tangent to the CRS's ellipsoid at its corner 0 (east and north of GeographicLib's
//    LocalCartesian, at height 0) and heights stay heights, so "level" means along the
//    ellipsoid; plan areas are geodesic areas on the ellipsoid (GeographicLib PolygonArea).
// Thread-safety: immutable; safe to share.
#pragma once

#include <array>
#include <memory>
#include <optional>

#include "core/base/status.h"
#include "core/geometry/crs.h"

namespace GeographicLib {
class Geocentric;
class Geodesic;
}  // namespace GeographicLib

namespace tinbase {

struct Vec3 {
  double x = 0;
  double y = 0;
  double z = 0;
};

struct Ellipsoid {
  double a = 6378137.0;          // equatorial radius, metres
  double f = 1 / 298.257223563;  // flattening (0: a sphere)
};

class MetricFrame {
 public:
  // Plan units of `metres_per_unit` metres, heights of `z_metres_per_unit` metres.
  static MetricFrame Projected(double metres_per_unit = 1, double z_metres_per_unit = 1);
  // Longitude / latitude in degrees on `ellipsoid`, heights of `z_metres_per_unit` metres.
  static MetricFrame Geographic(const Ellipsoid& ellipsoid, double z_metres_per_unit = 1);

  bool geographic() const { return ellipsoid_.has_value(); }
  const std::optional<Ellipsoid>& ellipsoid() const { return ellipsoid_; }
  // Metres per unit of height.
  double z_metres() const { return z_metres_; }

  // The corners (CRS x, y, z) in metres in a local Cartesian frame whose x axis points east (grid
  // east when projected) and z axis up, with corners[0] at the origin.
  std::array<Vec3, 3> Local(const std::array<Vec3, 3>& corners) const;
  // The plan area of the triangle in square metres: the area of the local frame's projection
  // when projected, the geodesic area of the triangle with geodesic edges when geographic. Not
  // signed. REQUIRES: geographic corners are within [-90, 90] latitude.
  double PlanArea(const std::array<Vec3, 3>& corners) const;

 private:
  MetricFrame(double xy, double z, std::optional<Ellipsoid> e);
  double xy_metres_ = 1;
  double z_metres_ = 1;
  std::optional<Ellipsoid> ellipsoid_;
  // Built once per frame: their constructors expand series in the flattening.
  std::shared_ptr<const GeographicLib::Geocentric> earth_;
  std::shared_ptr<const GeographicLib::Geodesic> geodesic_;
};

// The frame of a store's CRS: geographic on its ellipsoid, or projected in its linear unit; the
// vertical unit from Crs::VerticalMetresPerUnit. A null `crs` (a store before its first DEM)
// measures in the coordinates' own units. InvalidArgument when the CRS has no usable ellipsoid.
Result<MetricFrame> MetricFrameFor(const Crs* crs);

// Plan area of a local triangle (Local's output), not signed.
double LocalPlanArea(const std::array<Vec3, 3>& local);
// 3D area of a local triangle.
double LocalSurfaceArea(const std::array<Vec3, 3>& local);

}  // namespace tinbase
