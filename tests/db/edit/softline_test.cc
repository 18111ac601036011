// Softlines (issue 28, item 2): a softline's segments are edges of the surface like a
// breakline's, and its constraint rows are kind 'soft' through every later edit that splits them;
// every other row is 'hard'; `tinbase check` verifies both (constraint-kind) and the exports tell
// a soft line from a hard breakline.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "db/export/landxml_export.h"
#include "db/integrity_check.h"
#include "tests/support/edit_fixture.h"
#include "tests/support/line_features.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::kEditCx;
using testing::kEditCy;

class SoftlineTest : public testing::EditFixture {
 protected:
  // Adds one line feature of `mode`; returns its id.
  int64_t Add(FeatureMode mode, const std::vector<Point2>& points) {
    auto report = testing::AddLines(*store_, {testing::LineFeature("line", mode, points)});
    EXPECT_TRUE(report.ok()) << report.status().ToString();
    return report.ok() ? report->first_feature_id : 0;
  }

  void ExpectIntact() { testing::ExpectStoreIntact(*store_, /*full=*/true); }

  // The kinds of `feature`'s constraint rows, e.g. {"soft"}; the rows must be there.
  std::set<std::string> KindsOf(int64_t feature) {
    std::set<std::string> kinds;
    for (const auto& c : testing::ConstraintsOf(*store_, feature)) kinds.insert(c.kind);
    EXPECT_FALSE(kinds.empty()) << "feature " << feature << " has no constraint rows";
    return kinds;
  }

  const std::vector<Point2> soft_ = {{kEditCx - 1500, kEditCy - 900},
                                     {kEditCx + 100, kEditCy + 150},
                                     {kEditCx + 1500, kEditCy + 1100}};
  const std::vector<Point2> hard_ = {{kEditCx - 1200, kEditCy + 1000},
                                     {kEditCx + 1300, kEditCy - 1000}};
};

TEST_F(SoftlineTest, ASoftlinesRowsAreSoftAndItsSegmentsEdges) {
  const int64_t soft = Add(FeatureMode::kSoftline, soft_);
  EXPECT_EQ(KindsOf(soft), std::set<std::string>{"soft"});
  ExpectIntact();  // constraint-not-edge holds for soft rows too
  auto feature = LoadFeature(*store_, surface_, soft);
  ASSERT_TRUE(feature.ok());
  EXPECT_EQ(feature->mode, FeatureMode::kSoftline);
  EXPECT_EQ(feature->lines.size(), 1u);
}

// The breakline splits the softline's edge where they cross: the pieces stay soft, the
// breakline's rows are hard, and removing the softline takes its rows alone.
TEST_F(SoftlineTest, ABreaklineAcrossItKeepsTheSplitRowsSoft) {
  const int64_t soft = Add(FeatureMode::kSoftline, soft_);
  const size_t before = testing::ConstraintsOf(*store_, soft).size();
  const int64_t hard = Add(FeatureMode::kBreakline, hard_);
  EXPECT_GT(testing::ConstraintsOf(*store_, soft).size(), before) << "the crossing splits it";
  EXPECT_EQ(KindsOf(soft), std::set<std::string>{"soft"});
  EXPECT_EQ(KindsOf(hard), std::set<std::string>{"hard"});
  ExpectIntact();
  ASSERT_TRUE(RemovePolygon(*store_, soft).ok());
  EXPECT_TRUE(testing::ConstraintsOf(*store_, soft).empty());
  EXPECT_EQ(KindsOf(hard), std::set<std::string>{"hard"});
  ExpectIntact();
}

TEST_F(SoftlineTest, CheckReportsARowWhoseKindDisagreesWithItsFeature) {
  const int64_t soft = Add(FeatureMode::kSoftline, soft_);
  const int64_t hard = Add(FeatureMode::kBreakline, hard_);
  const auto s = testing::ConstraintsOf(*store_, soft).front();
  const auto h = testing::ConstraintsOf(*store_, hard).front();
  ASSERT_TRUE(
      store_->db()
          .Exec("UPDATE constraints SET kind = 'hard' WHERE feature = " + std::to_string(soft) +
                " AND va = " + std::to_string(s.va) + " AND vb = " + std::to_string(s.vb) +
                "; UPDATE constraints SET kind = 'soft' WHERE feature = " + std::to_string(hard) +
                " AND va = " + std::to_string(h.va) + " AND vb = " + std::to_string(h.vb))
          .ok());
  auto problems = CheckStore(*store_);
  ASSERT_TRUE(problems.ok());
  std::vector<std::string> found;
  for (const Problem& p : *problems) found.push_back(p.code + ": " + p.message);
  const auto text = [](const testing::ConstraintOf& c, const char* kind, const std::string& owner) {
    return "constraint-kind: surface 'terrain': constraint (" + std::to_string(c.va) + ", " +
           std::to_string(c.vb) + ") is kind '" + kind + "' but " + owner;
  };
  std::vector<std::string> expected = {
      text(s, "hard", "feature " + std::to_string(soft) + " is a softline"),
      text(h, "soft", "feature " + std::to_string(hard) + " is a breakline")};
  if (h.va < s.va || (h.va == s.va && h.vb < s.vb)) std::swap(expected[0], expected[1]);
  EXPECT_EQ(found, expected);
}

// LandXML: a breakline is a standard (slope-breaking) Breakline, a softline a nondestructive one
// (an edge that takes the surface's elevations and breaks no slope); the GeoPackage and PostGIS
// layers carry the mode and the kind (tests/db/migrations_test.cc).
TEST_F(SoftlineTest, LandXmlWritesASoftlineAsANondestructiveBreakline) {
  Add(FeatureMode::kSoftline, soft_);
  Add(FeatureMode::kBreakline, hard_);
  const std::string path = dir_.Path("s.xml");
  auto surface = LoadLandXmlSurface(*store_, surface_);
  ASSERT_TRUE(surface.ok()) << surface.status().ToString();
  Status written = ExportLandXml(*surface, path);
  ASSERT_TRUE(written.ok()) << written.ToString();
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string xml = text.str();
  EXPECT_NE(xml.find("brkType=\"nondestructive\""), std::string::npos);
  EXPECT_NE(xml.find("brkType=\"standard\""), std::string::npos);
}

}  // namespace
}  // namespace tinbase
