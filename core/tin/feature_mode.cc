#include "core/tin/feature_mode.h"

#include <string>

namespace tinbase {

const char* FeatureModeName(FeatureMode mode) {
  switch (mode) {
    case FeatureMode::kClip:
      return "clip";
    case FeatureMode::kErase:
      return "erase";
    case FeatureMode::kFill:
      return "fill";
    case FeatureMode::kReplace:
      return "replace";
    case FeatureMode::kBreakline:
      return "breakline";
    case FeatureMode::kSoftline:
      return "softline";
    case FeatureMode::kPoints:
      return "points";
  }
  return "?";  // not reached: the switch covers every mode
}

Result<FeatureMode> ParseFeatureMode(std::string_view name) {
  for (FeatureMode mode : kFeatureModes)
    if (name == FeatureModeName(mode)) return mode;
  return Status::InvalidArgument(
      "unknown feature mode '" + std::string(name) +
      "' (expected clip, erase, fill, replace, breakline, softline or points)");
}

const char* ZFromName(ZFrom z_from) { return z_from == ZFrom::kFeature ? "feature" : "dem"; }

Result<ZFrom> ParseZFrom(std::string_view name) {
  if (name == "dem") return ZFrom::kDem;
  if (name == "feature") return ZFrom::kFeature;
  return Status::InvalidArgument("unknown z source '" + std::string(name) +
                                 "' (expected dem or feature)");
}

}  // namespace tinbase
