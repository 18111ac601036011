// Which commands the CLI starts again on huge-page malloc (apps/tinbase/bulk_commands.h).
#include "apps/tinbase/bulk_commands.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/support/test_support.h"

namespace tinbase::cli {
namespace {

bool Bulk(std::vector<std::string> words) {
  words.insert(words.begin(), "tinbase");
  std::vector<const char*> argv;
  for (const std::string& w : words) argv.push_back(w.c_str());
  return TriangulatesInBulk(static_cast<int>(argv.size()), argv.data());
}

TEST(BulkCommandsTest, PointImportsTinBuildsAndContourDemsAreBulk) {
  EXPECT_TRUE(Bulk({"points", "import", "s.tinbase", "cloud.las", "--surface", "ground"}));
  EXPECT_TRUE(Bulk({"tin", "build", "s.tinbase", "--surface", "terrain"}));
  EXPECT_TRUE(Bulk({"dem", "from-contours", "s.tinbase", "contours.gpkg"}));
}

TEST(BulkCommandsTest, QueriesEditsAndDemImportsAreNot) {
  EXPECT_FALSE(Bulk({}));
  EXPECT_FALSE(Bulk({"--version"}));
  EXPECT_FALSE(Bulk({"info", "s.tinbase"}));
  EXPECT_FALSE(Bulk({"locate", "s.tinbase", "1", "2"}));
  EXPECT_FALSE(Bulk({"polygon", "add", "s.tinbase", "map.gpkg", "--mode", "fill"}));
  EXPECT_FALSE(Bulk({"dem"}));
  EXPECT_FALSE(Bulk({"dem", "import", "s.tinbase", "srtm.hgt"}));
  EXPECT_FALSE(Bulk({"export", "s.tinbase", "--surface", "terrain", "out.obj"}));
}

// Whole-surface reads restart for a store file of kLargeStoreBytes or more: sparse files of
// either side of the bound, and paths that are no file.
TEST(BulkCommandsTest, LargeStoresAreThoseOfTheBoundOrMore) {
  testing::TempDir dir;
  const std::string file = dir.Path("s.tinbase");
  std::ofstream(file).put('x');
  EXPECT_FALSE(IsLargeStore(file));
  std::filesystem::resize_file(file, kLargeStoreBytes - 1);
  EXPECT_FALSE(IsLargeStore(file));
  std::filesystem::resize_file(file, kLargeStoreBytes);
  EXPECT_TRUE(IsLargeStore(file));
  EXPECT_FALSE(IsLargeStore(dir.Path("missing.tinbase")));
  EXPECT_FALSE(IsLargeStore(dir.Path("")));
}

}  // namespace
}  // namespace tinbase::cli
