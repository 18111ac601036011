// SlopeAspect: the slope and aspect of each triangle of a TIN.
//
// A triangle is a plane z = z0 + gx x + gy y in its local metric frame (core/measure/
// metric_frame.h: x east, y north, metres); slope is atan(|g|) in degrees, 0 for a flat
// triangle, and aspect the compass direction the plane faces (downhill, -g), in degrees
// clockwise from north in [0, 360): 0 north, 90 east. North is grid north for a projected CRS
// (the meridian convergence is not removed) and true north for a geographic one. A flat
// triangle has no aspect. Thread-safety: pure function.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/measure/metric_frame.h"
#include "core/tin/tin.h"

namespace tinbase {

struct TriangleSlope {
  uint32_t triangle = 0;                 // index into Tin::triangles
  double slope_degrees = 0;              // [0, 90)
  std::optional<double> aspect_degrees;  // [0, 360); nullopt when flat
};

// One entry per triangle (visible ones only when `visible_only`), in triangle order.
// REQUIRES: no triangle is degenerate in plan.
std::vector<TriangleSlope> SlopeAndAspect(const Tin& tin, const MetricFrame& frame,
                                          bool visible_only);

}  // namespace tinbase
