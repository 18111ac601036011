// FeatureMode: what a feature does to the surface it is added to (docs/design.md, "Data model";
// core/tin/feature_paint.h has what each painting mode does to the triangles), and ZFrom: where a
// line feature's vertices take their z. Users name both as text (the CLI's --mode and --z-from,
// the `features.mode` and `features.z_from` columns); that text is parsed here once, where it
// comes in, and code past the edge compares enum values only. Thread-safety: pure functions.
#pragma once

#include <array>
#include <string_view>

#include "core/base/status.h"

namespace tinbase {

enum class FeatureMode {
  kClip,       // triangles outside the union of all clip polygons are hidden
  kErase,      // triangles inside are hidden
  kFill,       // triangles inside take the feature's tag
  kReplace,    // as fill, and the vertices inside take z = the feature's level
  kBreakline,  // a line whose segments become hard constrained edges; paints nothing
  // A line whose segments become edges for the surface's shape only: soft constrained edges,
  // exempt from the rules of hard breaklines (exports write no slope break for them;
  // docs/design.md, "Soft lines and z from the feature"). Paints nothing.
  kSoftline,
  kPoints  // surveyed mass points (one MultiPoint Z feature); paints nothing
};

inline constexpr std::array<FeatureMode, 7> kFeatureModes = {
    FeatureMode::kClip,      FeatureMode::kErase,    FeatureMode::kFill,  FeatureMode::kReplace,
    FeatureMode::kBreakline, FeatureMode::kSoftline, FeatureMode::kPoints};

// The canonical spelling, as the CLI takes it and the store keeps it: "clip", "erase", "fill",
// "replace", "breakline", "softline" or "points".
const char* FeatureModeName(FeatureMode mode);

// The mode `name` spells (exactly, lower case). InvalidArgument "unknown feature mode 'x'
// (expected clip, erase, fill, replace, breakline, softline or points)" otherwise.
Result<FeatureMode> ParseFeatureMode(std::string_view name);

// Whether the mode's geometry is lines (breakline, softline), whose segments become constraints.
inline bool IsLineMode(FeatureMode mode) {
  return mode == FeatureMode::kBreakline || mode == FeatureMode::kSoftline;
}
// Whether the mode's geometry is polygons (clip, erase, fill, replace).
inline bool IsPolygonMode(FeatureMode mode) {
  return !IsLineMode(mode) && mode != FeatureMode::kPoints;
}

// Where a line's vertices take their z: draped on the surface's DEM (as every line did before),
// or the feature's own z (3D lines: LineString Z, contours).
enum class ZFrom { kDem, kFeature };

// "dem" or "feature", as --z-from takes it and `features.z_from` keeps it.
const char* ZFromName(ZFrom z_from);
// InvalidArgument "unknown z source 'x' (expected dem or feature)" for any other text.
Result<ZFrom> ParseZFrom(std::string_view name);

}  // namespace tinbase
