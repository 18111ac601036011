#include "core/measure/metric_frame.h"

#include <ogr_spatialref.h>

#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <GeographicLib/PolygonArea.hpp>
#include <cmath>
#include <string>

namespace tinbase {

MetricFrame::MetricFrame(double xy, double z, std::optional<Ellipsoid> e)
    : xy_metres_(xy), z_metres_(z), ellipsoid_(e) {
  if (!e) return;
  earth_ = std::make_shared<const GeographicLib::Geocentric>(e->a, e->f);
  geodesic_ = std::make_shared<const GeographicLib::Geodesic>(e->a, e->f);
}

MetricFrame MetricFrame::Projected(double metres_per_unit, double z_metres_per_unit) {
  return MetricFrame(metres_per_unit, z_metres_per_unit, std::nullopt);
}

MetricFrame MetricFrame::Geographic(const Ellipsoid& ellipsoid, double z_metres_per_unit) {
  return MetricFrame(1, z_metres_per_unit, ellipsoid);
}

std::array<Vec3, 3> MetricFrame::Local(const std::array<Vec3, 3>& c) const {
  std::array<Vec3, 3> out;
  if (!ellipsoid_) {
    for (int i = 0; i < 3; ++i) {
      out[i] = {(c[i].x - c[0].x) * xy_metres_, (c[i].y - c[0].y) * xy_metres_,
                (c[i].z - c[0].z) * z_metres_};
    }
    return out;
  }
  // Plan positions on the tangent plane at corner 0, heights as heights: taking ENU's own up
  // axis would tilt every triangle by its distance from corner 0 over the earth's radius (the
  // curvature drop), which shows in the slope of gentle ground.
  const GeographicLib::LocalCartesian enu(c[0].y, c[0].x, 0, *earth_);
  for (int i = 0; i < 3; ++i) {
    double up = 0;
    enu.Forward(c[i].y, c[i].x, 0, out[i].x, out[i].y, up);
    out[i].z = (c[i].z - c[0].z) * z_metres_;
  }
  return out;
}

double MetricFrame::PlanArea(const std::array<Vec3, 3>& c) const {
  if (!ellipsoid_) {
    const double cross =
        (c[1].x - c[0].x) * (c[2].y - c[0].y) - (c[1].y - c[0].y) * (c[2].x - c[0].x);
    return 0.5 * std::abs(cross) * xy_metres_ * xy_metres_;
  }
  GeographicLib::PolygonArea polygon(*geodesic_);
  for (const Vec3& p : c) polygon.AddPoint(p.y, p.x);
  double perimeter = 0;
  double area = 0;
  // reverse = false, sign = true: a clockwise triangle gives a small negative area rather than
  // the rest of the ellipsoid.
  polygon.Compute(false, true, perimeter, area);
  return std::abs(area);
}

double LocalPlanArea(const std::array<Vec3, 3>& p) {
  return 0.5 *
         std::abs((p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x));
}

double LocalSurfaceArea(const std::array<Vec3, 3>& p) {
  const Vec3 u{p[1].x - p[0].x, p[1].y - p[0].y, p[1].z - p[0].z};
  const Vec3 v{p[2].x - p[0].x, p[2].y - p[0].y, p[2].z - p[0].z};
  const double nx = u.y * v.z - u.z * v.y;
  const double ny = u.z * v.x - u.x * v.z;
  const double nz = u.x * v.y - u.y * v.x;
  return 0.5 * std::sqrt(nx * nx + ny * ny + nz * nz);
}

Result<MetricFrame> MetricFrameFor(const Crs* crs) {
  if (crs == nullptr) return MetricFrame::Projected();
  const double z = crs->VerticalMetresPerUnit();
  if (!crs->IsGeographic()) {
    const double linear = crs->ogr().GetLinearUnits(nullptr);
    return MetricFrame::Projected(linear > 0 ? linear : 1, z);
  }
  OGRErr err = OGRERR_NONE;
  const double a = crs->ogr().GetSemiMajor(&err);
  if (err != OGRERR_NONE || !(a > 0))
    return Status::InvalidArgument("CRS " + crs->Label() + " has no ellipsoid to measure on");
  const double inverse_f = crs->ogr().GetInvFlattening(&err);
  if (err != OGRERR_NONE || inverse_f < 0)
    return Status::InvalidArgument("CRS " + crs->Label() + " has no ellipsoid flattening");
  // OGR spells a sphere as inverse flattening 0.
  return MetricFrame::Geographic({a, inverse_f == 0 ? 0.0 : 1 / inverse_f}, z);
}

}  // namespace tinbase
