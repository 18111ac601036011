// ExportFormat: every name parses back to its format, unknown names are refused with the list,
// and output paths' extensions pick the format.
#include "core/export/export_format.h"

#include <gtest/gtest.h>

namespace tinbase {
namespace {

TEST(ExportFormat, EveryNameParsesBackToItsFormat) {
  for (ExportFormat f : {ExportFormat::kObj, ExportFormat::kPly, ExportFormat::kStl,
                         ExportFormat::kGlb, ExportFormat::kGeoJson}) {
    auto parsed = ParseExportFormat(ExportFormatName(f));
    ASSERT_TRUE(parsed.ok()) << ExportFormatName(f);
    EXPECT_EQ(*parsed, f);
  }
  EXPECT_EQ(ExportFormatList(), "obj, ply, stl, glb, geojson");
}

TEST(ExportFormat, AnUnknownNameIsRefusedWithTheList) {
  for (const char* name : {"dxf", "OBJ", "", "gltf"}) {
    auto parsed = ParseExportFormat(name);
    ASSERT_FALSE(parsed.ok()) << name;
    EXPECT_EQ(parsed.status().code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(parsed.status().message(), "unknown export format '" + std::string(name) +
                                             "' (expected one of: obj, ply, stl, glb, geojson)");
  }
}

TEST(ExportFormat, TheExtensionPicksTheFormat) {
  EXPECT_EQ(ExportFormatFromPath("a/b/site.obj"), ExportFormat::kObj);
  EXPECT_EQ(ExportFormatFromPath("site.PLY"), ExportFormat::kPly);
  EXPECT_EQ(ExportFormatFromPath("site.stl"), ExportFormat::kStl);
  EXPECT_EQ(ExportFormatFromPath("site.v2.glb"), ExportFormat::kGlb);
  EXPECT_EQ(ExportFormatFromPath("site.geojson"), ExportFormat::kGeoJson);
  EXPECT_EQ(ExportFormatFromPath("site.json"), ExportFormat::kGeoJson);
  EXPECT_EQ(ExportFormatFromPath("site.gltf"), std::nullopt);
  EXPECT_EQ(ExportFormatFromPath("site"), std::nullopt);
  EXPECT_EQ(ExportFormatFromPath("dir.glb/site"), std::nullopt);
}

}  // namespace
}  // namespace tinbase
