// Profile: a surface's section along a polyline, every crossing of a triangle edge with its
// distance along the line and z, and the paint (visible, tag) of each stretch between them.
//
// Locates the line's first point (PointLocator), then follows the line across the stored
// neighbour links (core/query/line_walk.h), reading only the triangles it crosses through
// MeshTables, all in one read snapshot. Thread-safety: one call per Store at a time.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/predicates.h"
#include "core/query/line_walk.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

// The triangle under one stretch of the line and its paint.
struct ProfileStretch {
  int64_t triangle = 0;
  bool visible = true;
  std::optional<std::string> tag;
};

struct SurfaceProfile {
  std::vector<Station> stations;          // in order along the line (LineWalk)
  std::vector<ProfileStretch> stretches;  // stretches[i] from stations[i] to stations[i + 1]
  double length() const { return stations.empty() ? 0 : stations.back().distance; }
};

// The profile of `surface` along `line`. InvalidArgument "a profile line needs at least two
// points, got n" for fewer than two points, "... all its points are the same" when they coincide,
// naming point k (1-based) when a coordinate is not finite, and WalkLine's "the line leaves the
// surface at (x, y) ..."; NotFound "profile point 1 (x, y) is outside surface 's'" when the first
// point is; Corruption when the rows the walk reads are inconsistent.
Result<SurfaceProfile> ProfileAlong(Store& store, const SurfaceInfo& surface,
                                    const std::vector<Point2>& line);

}  // namespace tinbase
