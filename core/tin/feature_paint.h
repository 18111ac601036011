// Feature painting: every triangle's visibility and tag, recomputed from scratch from the
// surface's polygon features (docs/design.md, "Invariants", invariant 6; the modes come from
// paper 000 of docs/design.md, "Where the ideas come from", and are core/tin/feature_mode.h).
//
//   clip     triangles outside the union of all clip polygons are invisible (no clip feature:
//            nothing is hidden by clipping);
//   erase    triangles inside an erase polygon are invisible;
//   fill     triangles inside get the feature's tag; features are applied in order, so a later
//            one overrides an earlier one where they overlap;
//   replace  as fill, and the vertices inside or on its rings take z = level (reported apart,
//            since changing z is the update engine's decision, not a paint);
//   breakline  paints nothing (its segments are constrained edges, nothing more).
//
// "Inside" for a triangle is decided by its centroid, with an exact even-odd test against the
// polygons with their holes (PolygonLocator), so a triangle is never on both sides of a ring.
// The update engine uses this to check its incremental flood fill and the checker to verify
// invariant 6. Thread-safety: pure functions over the given values.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/polygon.h"
#include "core/geometry/polygon_locator.h"
#include "core/tin/feature_mode.h"
#include "core/tin/tin.h"

namespace tinbase {

struct PaintedFeature {
  // The union of the feature's polygons (valid, MakeValidPolygon, in the surface's CRS), shared
  // because the editor keeps it between transactions; null when none are near the triangles.
  std::shared_ptr<const PolygonLocator> inside;
  FeatureMode mode = FeatureMode::kFill;  // a breakline paints nothing
  int32_t tag = kNoTag;  // fill/replace: index into Tin::tags; kNoTag clears the tag
  double level = 0;      // replace: the z its vertices take
};

struct VertexLevel {
  uint32_t vertex = 0;
  double z = 0;
};

struct Paint {
  std::vector<uint8_t> visible;     // per triangle, 1 visible
  std::vector<int32_t> tag;         // per triangle, index into Tin::tags or kNoTag
  std::vector<VertexLevel> levels;  // by vertex index; the last replace covering it wins
};

// The paint `features` (in order) give `tin`'s triangles and vertices, starting from all
// visible and untagged. Each feature visits the triangles whose centroids lie in its box.
// REQUIRES: every feature's tag is kNoTag or an index into tin.tags.
Paint ComputePaint(const Tin& tin, const std::vector<PaintedFeature>& features);

// Sets each triangle's visible and tag from `paint`, and with `apply_levels` each replaced
// vertex's z. REQUIRES: `paint` was computed for `tin` (same sizes).
void ApplyPaint(const Paint& paint, Tin& tin, bool apply_levels);

}  // namespace tinbase
