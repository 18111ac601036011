// ExportFeature: a surface's feature as the mesh exports describe it (the GLB's property table,
// core/export/glb_writer.h), and which feature each triangle belongs to.
//
// A triangle belongs to the feature that gave it its tag: the last fill or replace feature (in
// the given order, the store's id order) whose polygons hold its centroid, the rule of
// core/tin/feature_paint.h. Clip, erase and breakline features own no triangles (they hide or
// constrain, they do not say what a triangle is) but still appear in the table. Thread-safety:
// pure functions.
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/polygon_locator.h"
#include "core/tin/feature_mode.h"
#include "core/tin/tin.h"

namespace tinbase {

struct ExportFeature {
  int64_t id = 0;  // store id
  FeatureMode mode = FeatureMode::kFill;
  std::optional<std::string> tag;
  nlohmann::json attributes = nlohmann::json::object();  // the feature's own key/value pairs
  // The union of its polygons; null for a breakline or a feature without polygons.
  std::shared_ptr<const PolygonLocator> inside;
};

inline constexpr int32_t kNoFeature = -1;

// For every triangle of `tin`, the index into `features` of the feature it belongs to (see the
// header comment), or kNoFeature.
std::vector<int32_t> OwningFeatures(const Tin& tin, const std::vector<ExportFeature>& features);

}  // namespace tinbase
