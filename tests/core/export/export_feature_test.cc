// OwningFeatures: a triangle belongs to the last fill or replace feature holding its centroid;
// clip, erase and breakline features own nothing.
#include "core/export/export_feature.h"

#include <gtest/gtest.h>

#include "tests/support/grid_tin.h"

namespace tinbase {
namespace {

ExportFeature Square(int64_t id, FeatureMode mode, double x0, double y0, double x1, double y1) {
  Polygon p;
  p.shell = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  ExportFeature f;
  f.id = id;
  f.mode = mode;
  f.inside = std::make_shared<PolygonLocator>(std::vector<Polygon>{p});
  return f;
}

TEST(OwningFeatures, TheLastFillOrReplaceHoldingTheCentroidWins) {
  const Tin tin = testing::MakeGridTin(10, 10, 1.0);  // [0, 10] x [0, 10]
  const std::vector<ExportFeature> features = {
      Square(1, FeatureMode::kFill, 0, 0, 6, 10),     // west
      Square(2, FeatureMode::kReplace, 4, 0, 10, 5),  // south east, over the west one
      Square(3, FeatureMode::kErase, 0, 0, 10, 10),   // hides all, owns nothing
      Square(4, FeatureMode::kClip, 0, 0, 10, 10),
      ExportFeature{5, FeatureMode::kBreakline, std::nullopt, nlohmann::json::object(), nullptr},
  };
  const std::vector<int32_t> owner = OwningFeatures(tin, features);
  ASSERT_EQ(owner.size(), tin.triangles.size());
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    double cx = 0, cy = 0;
    for (uint32_t v : tin.triangles[t].v) cx += tin.vertices[v].x / 3, cy += tin.vertices[v].y / 3;
    const int32_t want = (cx > 4 && cy < 5) ? 1 : (cx < 6 ? 0 : kNoFeature);
    EXPECT_EQ(owner[t], want) << "centroid " << cx << ", " << cy;
  }
}

TEST(OwningFeatures, NoFeaturesOwnNothing) {
  const Tin tin = testing::MakeGridTin(3, 3, 1.0);
  const std::vector<int32_t> owner = OwningFeatures(tin, {});
  EXPECT_EQ(owner, std::vector<int32_t>(tin.triangles.size(), kNoFeature));
}

}  // namespace
}  // namespace tinbase
