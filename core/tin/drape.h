// Drape: a plan-view polyline laid on an elevation surface (docs/design.md, "Inserting a
// polygon", step 2). Vertices take the surface's z; a segment is split at its midpoint,
// recursively, while the surface departs from the straight 3D segment there by more than the
// tolerance and the pieces are still longer than `min_spacing` (about a DEM cell: below that the
// DEM has no more detail to follow). Thread-safety: pure function.
#pragma once

#include <functional>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/cdt.h"
#include "core/geometry/polygon.h"
#include "core/tin/tin.h"

namespace tinbase {

// The elevation the polyline is laid on, at a plan position. NaN means "no data here" (outside the
// surface or on nodata); an error means the elevation could not be read (a DEM block that fails
// to load), which is a different thing and travels back as that error.
using DrapeElevationFn = std::function<Result<double>(double x, double y)>;

struct DrapeOptions {
  double tolerance = 1.0;    // metres, > 0
  double min_spacing = 1.0;  // map units, > 0
  bool closed = false;       // a ring: the last vertex joins the first
};

// The draped, densified polyline (kind kRing). InvalidArgument "vertex v: no elevation at (x, y)"
// where `elevation` gives NaN (outside the DEM or on nodata) at an input vertex or an inserted one;
// an error of `elevation` is returned with its code, as "vertex v: <its message>".
Result<std::vector<TinVertex>> DrapePolyline(const std::vector<Point2>& points,
                                             const DrapeElevationFn& elevation,
                                             const DrapeOptions& options);

}  // namespace tinbase
