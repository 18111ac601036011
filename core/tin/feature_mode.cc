#include "core/tin/feature_mode.h"

#include <string>

#include "core/base/message_text.h"

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
  std::string message = "unknown feature mode ";
  message.append(QuotedForMessage(name));
  message.append(" (expected clip, erase, fill, replace, breakline, softline or points)");
  return Status::InvalidArgument(message);
}

const char* ZFromName(ZFrom z_from) { return z_from == ZFrom::kFeature ? "feature" : "dem"; }

Result<ZFrom> ParseZFrom(std::string_view name) {
  if (name == "dem") return ZFrom::kDem;
  if (name == "feature") return ZFrom::kFeature;
  std::string message = "unknown z source ";
  message.append(QuotedForMessage(name));
  message.append(" (expected dem or feature)");
  return Status::InvalidArgument(message);
}

}  // namespace tinbase
