// Bulk point location: the triangle, z and paint under each of many points of one surface,
// handed over one at a time in input order so a caller can stream them out.
//
// A point in the triangle of the previous answer is answered from memory (steps 0): sorted input
// puts several points in a row into one triangle. Otherwise one PointLocator serves every point,
// so each walk starts from the previous answer: points sorted along a path or in space cost a
// few steps each, and only a point far from the one before jumps first (db/point_locator.h). A
// point on an edge may be answered by either triangle (their z agree). All answers come from one
// read snapshot.
// Thread-safety: one call per Store at a time.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/predicates.h"
#include "db/point_locator.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

// Receives point `index` of the input and where it lies: null for a point outside the surface.
// A non-ok Status stops the run and is returned by LocatePoints.
using LocatedPointSink =
    std::function<Status(size_t index, const Point2& point, const Location* where)>;

// Locates each of `points` on `surface`, in order, calling `sink` once per point. A point
// outside the surface is an answer (null), not an error. Errors: the sink's, and PointLocator's
// other than NotFound (Corruption when the rows a walk reads are inconsistent).
// REQUIRES: finite coordinates.
Status LocatePoints(Store& store, const SurfaceInfo& surface, const std::vector<Point2>& points,
                    const LocatedPointSink& sink);

}  // namespace tinbase
