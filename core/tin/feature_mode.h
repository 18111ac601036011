// FeatureMode: what a feature does to the surface it is added to (docs/design.md, "Data model";
// core/tin/feature_paint.h has what each painting mode does to the triangles). Users name a mode
// as text (the CLI's --mode, the `features.mode` column); that text is parsed here once, where it
// comes in, and code past the edge compares enum values only. Thread-safety: pure functions.
#pragma once

#include <array>
#include <string_view>

#include "core/base/status.h"

namespace tinbase {

enum class FeatureMode {
  kClip,      // triangles outside the union of all clip polygons are hidden
  kErase,     // triangles inside are hidden
  kFill,      // triangles inside take the feature's tag
  kReplace,   // as fill, and the vertices inside take z = the feature's level
  kBreakline,  // a line whose segments become constrained edges; paints nothing
  kPoints      // survey points with their own z (db/edit/mass_points.h); paints nothing
};

inline constexpr std::array<FeatureMode, 6> kFeatureModes = {
    FeatureMode::kClip,    FeatureMode::kErase,     FeatureMode::kFill,
    FeatureMode::kReplace, FeatureMode::kBreakline, FeatureMode::kPoints};

// The canonical spelling, as the CLI takes it and the store keeps it: "clip", "erase", "fill",
// "replace", "breakline" or "points".
const char* FeatureModeName(FeatureMode mode);

// The mode `name` spells (exactly, lower case). InvalidArgument "unknown feature mode 'x'
// (expected clip, erase, fill, replace or breakline)" otherwise.
Result<FeatureMode> ParseFeatureMode(std::string_view name);

}  // namespace tinbase
