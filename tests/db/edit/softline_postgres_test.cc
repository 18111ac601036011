// Softlines and 3D lines on a PostgreSQL store: the same edits as on SQLite (softline_test.cc,
// zfrom_test.cc) through the SQL seam: the constraint kinds are written and split as on SQLite,
// and `tinbase check --full` verifies kinds and z there too.
#include <gtest/gtest.h>

#include "db/dem_store.h"
#include "db/integrity_check.h"
#include "db/surface_builder.h"
#include "tests/support/edit_fixture.h"
#include "tests/support/line_features.h"
#include "tests/support/postgres_support.h"

namespace tinbase {
namespace {

using testing::kEditCx;
using testing::kEditCy;

std::vector<std::string> ProblemsOf(Store& store) {
  auto problems = CheckStore(store, {.surface = {}, .full = true});
  EXPECT_TRUE(problems.ok()) << problems.status().ToString();
  std::vector<std::string> out;
  if (problems.ok())
    for (const Problem& p : *problems) out.push_back(p.code + ": " + p.message);
  return out;
}

TEST(SoftlinePostgresTest, KindsAndZHoldOnPostgres) {
  const std::string target = testing::FreshPostgresStore("softline");
  ASSERT_FALSE(target.empty());
  auto created = Store::Create(target, "");
  ASSERT_TRUE(created.ok()) << created.status().ToString();
  Store& store = **created;
  DemStore dems(store);
  ASSERT_TRUE(dems.Import({testing::DataPath("geology/hamersley/dtm_rp.tif")}, {}).ok());
  SurfaceBuildOptions o;
  o.surface = "terrain";
  o.greedy.tolerance = 5;
  ASSERT_TRUE(BuildSurfaceFromDem(store, o).ok());

  const Point2 a{kEditCx - 1500, kEditCy - 900}, b{kEditCx + 1500, kEditCy + 1100};
  const Point2 c{kEditCx - 1200, kEditCy + 1000}, d{kEditCx + 1300, kEditCy - 1000};
  auto soft =
      testing::AddLines(store, {testing::LineFeature("soft", FeatureMode::kSoftline, {a, b})});
  ASSERT_TRUE(soft.ok()) << soft.status().ToString();
  auto line3d = testing::AddLines(
      store,
      {testing::LineFeature("3d", FeatureMode::kBreakline, {c, d}, std::vector<double>{900, 950})});
  ASSERT_TRUE(line3d.ok()) << line3d.status().ToString();
  const auto soft_rows = testing::ConstraintsOf(store, soft->first_feature_id);
  ASSERT_GE(soft_rows.size(), 2u) << "the 3D line splits the softline";
  for (const auto& row : soft_rows) EXPECT_EQ(row.kind, "soft");
  for (const auto& row : testing::ConstraintsOf(store, line3d->first_feature_id)) {
    EXPECT_EQ(row.kind, "hard");
    EXPECT_GE(row.az, 900);
    EXPECT_LE(row.az, 950);
  }
  EXPECT_EQ(ProblemsOf(store), std::vector<std::string>{});

  ASSERT_TRUE(store.db()
                  .Exec("UPDATE constraints SET kind = 'hard' WHERE feature = " +
                        std::to_string(soft->first_feature_id))
                  .ok());
  const auto problems = ProblemsOf(store);
  ASSERT_EQ(problems.size(), soft_rows.size());
  EXPECT_NE(problems.front().find("constraint-kind: surface 'terrain': constraint ("),
            std::string::npos)
      << problems.front();
}

}  // namespace
}  // namespace tinbase
