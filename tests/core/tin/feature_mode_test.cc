// FeatureMode: every mode's canonical spelling parses back to it, and anything else is refused
// with a message naming the bad value and the accepted ones.
#include "core/tin/feature_mode.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace tinbase {
namespace {

TEST(FeatureMode, EveryModeRoundTripsThroughItsSpelling) {
  std::set<std::string> spellings;
  for (FeatureMode mode : kFeatureModes) {
    const std::string name = FeatureModeName(mode);
    spellings.insert(name);
    auto parsed = ParseFeatureMode(name);
    ASSERT_TRUE(parsed.ok()) << parsed.status().ToString();
    EXPECT_EQ(*parsed, mode) << name;
  }
  EXPECT_EQ(spellings, (std::set<std::string>{"clip", "erase", "fill", "replace", "breakline",
                                              "softline", "points"}));
}

TEST(FeatureMode, AnythingElseIsRefusedNamingTheValueAndTheChoices) {
  for (const std::string bad : {"paint", "", "Fill", "fill ", "clip,erase", "break line"}) {
    auto parsed = ParseFeatureMode(bad);
    ASSERT_FALSE(parsed.ok()) << "'" << bad << "'";
    EXPECT_EQ(parsed.status().code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(parsed.status().message(),
              "unknown feature mode '" + bad +
                  "' (expected clip, erase, fill, replace, breakline, softline or points)");
  }
}

}  // namespace
}  // namespace tinbase
