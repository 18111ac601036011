#include "core/measure/slope_aspect.h"

#include <cmath>
#include <numbers>

namespace tinbase {

namespace {

constexpr double kDegrees = 180 / std::numbers::pi;

TriangleSlope SlopeOf(const Tin& tin, uint32_t index, const MetricFrame& frame) {
  const TinTriangle& t = tin.triangles[index];
  std::array<Vec3, 3> corners;
  for (int i = 0; i < 3; ++i) {
    const TinVertex& v = tin.vertices[t.v[i]];
    corners[i] = {v.x, v.y, v.z};
  }
  const std::array<Vec3, 3> p = frame.Local(corners);
  const Vec3 u{p[1].x - p[0].x, p[1].y - p[0].y, p[1].z - p[0].z};
  const Vec3 w{p[2].x - p[0].x, p[2].y - p[0].y, p[2].z - p[0].z};
  // The normal (nx, ny, nz) of a counter-clockwise triangle points up (nz > 0); the plane's
  // gradient is (-nx / nz, -ny / nz), so downhill is (nx, ny).
  const double nx = u.y * w.z - u.z * w.y;
  const double ny = u.z * w.x - u.x * w.z;
  const double nz = u.x * w.y - u.y * w.x;
  TriangleSlope out;
  out.triangle = index;
  const double horizontal = std::hypot(nx, ny);
  out.slope_degrees = std::atan2(horizontal, std::abs(nz)) * kDegrees;
  if (horizontal > 0) {
    const double sign = nz < 0 ? -1 : 1;  // a clockwise input triangle still faces up
    double aspect = std::atan2(sign * nx, sign * ny) * kDegrees;
    if (aspect < 0) aspect += 360;
    if (aspect >= 360) aspect -= 360;
    out.aspect_degrees = aspect;
  }
  return out;
}

}  // namespace

std::vector<TriangleSlope> SlopeAndAspect(const Tin& tin, const MetricFrame& frame,
                                          bool visible_only) {
  std::vector<TriangleSlope> out;
  out.reserve(tin.triangles.size());
  for (uint32_t i = 0; i < tin.triangles.size(); ++i) {
    if (visible_only && !tin.triangles[i].visible) continue;
    out.push_back(SlopeOf(tin, i, frame));
  }
  return out;
}

}  // namespace tinbase
