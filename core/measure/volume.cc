#include "core/measure/volume.h"

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include "core/measure/plan_overlay.h"

namespace tinbase {

namespace {

// Integrates d (in CRS height units, linear on each piece) over the pieces, fanning each convex
// piece into triangles from its first point.
VolumeReport Integrate(const Tin& a, const Tin* b, const PlanRegion* region,
                       const MetricFrame& frame,
                       const std::function<double(const OverlayPiece&, const Point2&)>& d) {
  VolumeReport report;
  ForEachOverlayPiece(a, b, region, [&](const OverlayPiece& piece) {
    const auto corner = [&](const Point2& r) {
      return Vec3{piece.origin.x + r.x, piece.origin.y + r.y, 0};
    };
    const double d0 = d(piece, piece.ring[0]);
    double d1 = d(piece, piece.ring[1]);
    for (size_t i = 1; i + 1 < piece.ring.size(); ++i) {
      const double d2 = d(piece, piece.ring[i + 1]);
      const double area =
          frame.PlanArea({corner(piece.ring[0]), corner(piece.ring[i]), corner(piece.ring[i + 1])});
      report.plan_area += area;
      const double m = frame.z_metres();
      report.split += SplitTriangle(area, {d0 * m, d1 * m, d2 * m});
      d1 = d2;
    }
  });
  return report;
}

std::string Number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

Result<VolumeReport> VolumeAgainstLevel(const Tin& tin, double level, const MetricFrame& frame,
                                        const PlanRegion* region) {
  if (!std::isfinite(level))
    return Status::InvalidArgument("level must be a finite number, got " + Number(level));
  VolumeReport report =
      Integrate(tin, nullptr, region, frame, [&](const OverlayPiece& p, const Point2& r) {
        return PlaneZ(tin, p.a, p.origin, r) - level;
      });
  if (!(report.plan_area > 0))
    return Status::InvalidArgument(region != nullptr ? "no visible triangle inside the polygon"
                                                     : "the surface has no visible triangle");
  return report;
}

Result<VolumeReport> VolumeBetween(const Tin& base, const Tin& top, const MetricFrame& frame,
                                   const PlanRegion* region) {
  VolumeReport report =
      Integrate(base, &top, region, frame, [&](const OverlayPiece& p, const Point2& r) {
        return PlaneZ(top, static_cast<uint32_t>(p.b), p.origin, r) -
               PlaneZ(base, p.a, p.origin, r);
      });
  if (!(report.plan_area > 0))
    return Status::InvalidArgument(region != nullptr
                                       ? "the surfaces do not overlap inside the polygon"
                                       : "the surfaces do not overlap");
  return report;
}

}  // namespace tinbase
