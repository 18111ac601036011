// Volumes of a TIN: against a horizontal level, and between two TINs (cut and fill, or the
// thickness of a formation between its base and top surfaces).
//
// Both integrate a linear difference over the convex pieces of core/measure/plan_overlay.h with
// the exact split of core/measure/level_split.h, so a surface that is a plane (or two surfaces
// whose difference is) gives the exact answer up to rounding, and a curved one converges as the
// triangulation is refined (the TIN's own interpolation is what is integrated). Only visible
// triangles count: an invisible triangle is no data. Results are in metres (m2, m3) through a
// MetricFrame. This is the plain C++ entry point other exporters compare with (the OpenVDB fog
// volume between two surfaces, say). Thread-safety: pure functions.
#pragma once

#include "core/base/status.h"
#include "core/measure/level_split.h"
#include "core/measure/metric_frame.h"
#include "core/measure/plan_region.h"
#include "core/tin/tin.h"

namespace tinbase {

struct VolumeReport {
  // For a level: above = the surface above the level (d = z - level); for two surfaces: above =
  // `top` above `base` (fill, d = top - base), below = `top` below `base` (cut).
  SplitMeasure split;
  double plan_area = 0;  // the plan area measured over (m2)
};

// The volume between `tin` and the horizontal plane z = level, over the visible triangles (and
// inside `region` when not null). InvalidArgument when `level` is not finite (naming it), or
// nothing visible lies inside the region.
Result<VolumeReport> VolumeAgainstLevel(const Tin& tin, double level, const MetricFrame& frame,
                                        const PlanRegion* region = nullptr);

// The volume between two surfaces where both are visible (and inside `region` when not null):
// split.above_volume is where `top` lies above `base` (for existing ground `base` and a design
// `top`, the fill), split.below_volume where it lies below (the cut). InvalidArgument "the
// surfaces do not overlap" (with " inside the polygon" when a region is given) when the common
// visible plan area is zero. Linear in the triangles when both are of similar size.
Result<VolumeReport> VolumeBetween(const Tin& base, const Tin& top, const MetricFrame& frame,
                                   const PlanRegion* region = nullptr);

}  // namespace tinbase
