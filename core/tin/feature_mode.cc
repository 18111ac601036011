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
    case FeatureMode::kPoints:
      return "points";
  }
  return "?";  // not reached: the switch covers every mode
}

Result<FeatureMode> ParseFeatureMode(std::string_view name) {
  for (FeatureMode mode : kFeatureModes)
    if (name == FeatureModeName(mode)) return mode;
  return Status::InvalidArgument("unknown feature mode '" + std::string(name) +
                                 "' (expected clip, erase, fill, replace or breakline)");
}

}  // namespace tinbase
