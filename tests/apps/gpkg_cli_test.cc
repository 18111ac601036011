// `tinbase export --format gpkg` end to end on the bundled Hamersley data (the demo's store: a
// DEM, a TIN and 61 geological units): GDAL's ogrinfo and gdalinfo read the file back with the
// counts `tinbase info` reports and the rows `tinbase neighbours` prints; bad input is refused
// with one line and no file. The store itself opens in GDAL's GeoPackage driver under its own
// name (migration 0013), an older store does once migrated, and another program's GeoPackage is
// not taken for a store.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "db/migrations.h"
#include "db/sql/connection.h"
#include "db/store.h"
#include "tests/support/cli_support.h"
#include "tests/support/gdal_tools.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::CliResult;
using testing::ExpectRejected;
using testing::HaveTool;
using testing::Json;
using testing::Quote;
using testing::RunCli;
using testing::RunTool;
using testing::TempDir;
using testing::ValueAfter;

class GpkgCliTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const CliResult demo =
        RunCli("demo --workdir " + Quote(dir_->dir()) + " --data " + Quote(TINBASE_TEST_DATA_DIR));
    ASSERT_EQ(demo.exit_code, 0) << demo.err;
    store_ = dir_->Path("demo.tinbase");
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override { ASSERT_TRUE(HaveTool("ogrinfo") && HaveTool("gdalinfo")); }

  static int64_t Count(const std::string& path, const std::string& layer) {
    auto r = RunTool("ogrinfo -ro -so " + Quote(path) + " " + layer);
    EXPECT_EQ(r.exit_code, 0) << r.out;
    const std::string value = ValueAfter(r.out, "Feature Count: ");
    return value.empty() ? -1 : std::stoll(value);
  }

  static TempDir* dir_;
  static std::string store_;
};

TempDir* GpkgCliTest::dir_ = nullptr;
std::string GpkgCliTest::store_;

TEST_F(GpkgCliTest, EveryLayerReadsBackWithTheStoresCounts) {
  const std::string out = dir_->Path("terrain.gpkg");
  const nlohmann::json report = Json(RunCli(
      "export " + Quote(store_) + " --surface terrain --format gpkg --json -o " + Quote(out)));
  const nlohmann::json info = Json(RunCli("info --json " + Quote(store_)));
  const nlohmann::json& surface = info["surfaces"][0];
  EXPECT_EQ(report["triangles"], surface["triangles"]);
  EXPECT_EQ(report["dem"], "dtm_rp");
  EXPECT_EQ(Count(out, "triangles"), surface["triangles"].get<int64_t>());
  EXPECT_EQ(Count(out, "constraints"), surface["constraints"].get<int64_t>());
  EXPECT_EQ(Count(out, "features") + Count(out, "breaklines"), surface["features"].get<int64_t>());

  const nlohmann::json& dem = info["dems"][0];
  auto raster = RunTool("gdalinfo -stats " + Quote(out));
  std::filesystem::remove(out + ".aux.xml");
  ASSERT_EQ(raster.exit_code, 0) << raster.out;
  EXPECT_EQ(ValueAfter(raster.out, "Size is "), dem["width"].dump() + ", " + dem["height"].dump());
  EXPECT_NE(raster.out.find("Type=Float32"), std::string::npos) << raster.out;
  EXPECT_EQ(ValueAfter(raster.out, "STATISTICS_MINIMUM="), "297");
  EXPECT_EQ(ValueAfter(raster.out, "STATISTICS_MAXIMUM="), "1175");
  auto coverage = RunTool("ogrinfo -ro " + Quote(out) +
                          " -sql \"SELECT datatype FROM gpkg_2d_gridded_coverage_ancillary\"");
  EXPECT_NE(coverage.out.find("datatype (String) = float"), std::string::npos) << coverage.out;
}

TEST_F(GpkgCliTest, TrianglesCarryTheNeighboursTheStoreHas) {
  const std::string out = dir_->Path("rows.gpkg");
  ASSERT_EQ(RunCli("export " + Quote(store_) + " --surface terrain --format gpkg -o " + Quote(out))
                .exit_code,
            0);
  for (int64_t id : {1, 24399, 50937}) {
    const nlohmann::json row = Json(
        RunCli("neighbours --json " + Quote(store_) + " --surface terrain " + std::to_string(id)));
    auto dump = RunTool("ogrinfo -ro " + Quote(out) + " triangles -fid " + std::to_string(id));
    ASSERT_EQ(dump.exit_code, 0) << dump.out;
    EXPECT_NE(dump.out.find("OGRFeature(triangles):" + std::to_string(id)), std::string::npos)
        << dump.out;
    for (int k = 0; k < 3; ++k) {
      const nlohmann::json& n = row["neighbours"][k];
      std::string key = "n";  // built in steps: GCC 12 warns on the one-line sum (-Wrestrict)
      key += std::to_string(k);
      key += " (Integer64) = ";
      EXPECT_EQ(ValueAfter(dump.out, key), n.is_null() ? "(null)" : n.dump()) << "triangle " << id;
    }
    EXPECT_EQ(ValueAfter(dump.out, "visible (Integer(Boolean)) = "),
              row["visible"].get<bool>() ? "1" : "0");
    EXPECT_EQ(ValueAfter(dump.out, "tag (String) = "),
              row["tag"].is_null() ? "(null)" : row["tag"].get<std::string>());
  }
}

TEST_F(GpkgCliTest, FiltersApply) {
  const std::string out = dir_->Path("granite.gpkg");
  const nlohmann::json report =
      Json(RunCli("export " + Quote(store_) +
                  " --surface terrain --format gpkg --json --visible-only --dem none "
                  "--bbox 530000,7490000,545000,7505000 --tag 'Bunjinah Formation' -o " +
                  Quote(out)));
  EXPECT_GT(report["triangles"].get<int64_t>(), 0);
  EXPECT_TRUE(report["dem"].is_null());
  EXPECT_EQ(Count(out, "triangles"), report["triangles"].get<int64_t>());
  auto others = RunTool("ogrinfo -ro " + Quote(out) +
                        " -sql \"SELECT count(*) AS n FROM triangles WHERE tag <> 'Bunjinah "
                        "Formation' OR visible = 0\"");
  EXPECT_NE(others.out.find("n (Integer) = 0"), std::string::npos) << others.out;
  auto raster = RunTool("gdalinfo " + Quote(out));
  EXPECT_EQ(raster.out.find("Size is"), std::string::npos) << "--dem none writes no raster";
}

// --feature: the inside of one geological unit, and that unit alone in the features layer.
TEST_F(GpkgCliTest, FeatureSelectsItsInside) {
  const std::string out = dir_->Path("unit.gpkg");
  const nlohmann::json report = Json(RunCli("export " + Quote(store_) +
                                            " --surface terrain --format gpkg --json --feature 1 "
                                            "-o " +
                                            Quote(out)));
  EXPECT_GT(report["triangles"].get<int64_t>(), 0);
  EXPECT_EQ(report["features"], 1);
  EXPECT_EQ(Count(out, "triangles"), report["triangles"].get<int64_t>());
  auto unit = RunTool("ogrinfo -ro " + Quote(out) + " features -fid 1");
  EXPECT_NE(unit.out.find("OGRFeature(features):1"), std::string::npos) << unit.out;
  auto tags = RunTool("ogrinfo -ro " + Quote(out) +
                      " -sql \"SELECT count(DISTINCT tag) AS n FROM triangles\"");
  EXPECT_NE(tags.out.find("n (Integer) = 1"), std::string::npos) << "one unit, one tag\n"
                                                                 << tags.out;
}

TEST_F(GpkgCliTest, BadInputLeavesNoFile) {
  const std::string out = dir_->Path("bad.gpkg");
  const std::string export_gpkg = "export " + Quote(store_) + " --surface terrain --format gpkg ";
  ExpectRejected(store_, export_gpkg + "-o " + Quote(dir_->Path("no/such/dir/x.gpkg")),
                 "no/such/dir/x.gpkg");
  ExpectRejected(store_, export_gpkg + "--bbox 0,0,10,10 -o " + Quote(out),
                 "nothing selected: surface 'terrain' has no triangles for bbox 0,0,10,10");
  ExpectRejected(store_, export_gpkg + "--bbox 0,0,10 -o " + Quote(out), "--bbox");
  ExpectRejected(store_, export_gpkg + "--dem nope -o " + Quote(out), "no DEM named 'nope'");
  ExpectRejected(store_, "export " + Quote(store_) + " --format gpkg -o " + Quote(out),
                 "--surface");
  for (const auto& entry : std::filesystem::directory_iterator(dir_->dir()))
    EXPECT_EQ(entry.path().filename().string().find("bad.gpkg"), std::string::npos)
        << "left behind: " << entry.path();
}

TEST_F(GpkgCliTest, TheStoreOpensAsAGeoPackageByItsOwnName) {
  const nlohmann::json info = Json(RunCli("info --json " + Quote(store_)));
  auto r = RunTool("ogrinfo -ro -so " + Quote(store_) + " tinbase_triangles");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("using driver `GPKG'"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Geometry: 3D Polygon"), std::string::npos) << r.out;
  EXPECT_EQ(ValueAfter(r.out, "Feature Count: "),
            std::to_string(info["surfaces"][0]["triangles"].get<int64_t>()))
      << r.out;
}

// Copies into `db` (an older schema) the rows of every table of `source` it also has, in the
// columns it has; the older schema's own rows of meta are kept.
void CopyRowsOfOlderSchema(Connection& db, const std::string& source) {
  ASSERT_TRUE(db.Exec("ATTACH DATABASE '" + source + "' AS src").ok());
  auto tables = db.Prepare(
      "SELECT name FROM main.sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite_%' "
      "AND name NOT LIKE 'gpkg_%' AND name <> 'meta' AND name IN (SELECT name FROM "
      "src.sqlite_master WHERE type = 'table')");
  ASSERT_TRUE(tables.ok()) << tables.status().ToString();
  std::vector<std::string> names;
  while (true) {
    auto row = (*tables)->Step();
    ASSERT_TRUE(row.ok()) << row.status().ToString();
    if (!*row) break;
    names.push_back((*tables)->ColumnText(0));
  }
  (*tables).reset();  // finished before the writes
  ASSERT_TRUE(db.Exec("PRAGMA foreign_keys = OFF").ok());
  for (const std::string& table : names) {
    auto columns = db.Prepare("SELECT group_concat('\"' || name || '\"') FROM pragma_table_info('" +
                              table + "', 'main')");
    ASSERT_TRUE(columns.ok() && *(*columns)->Step()) << table;
    const std::string list = (*columns)->ColumnText(0);
    ASSERT_TRUE(db.Exec("DELETE FROM main.\"" + table + "\"; INSERT INTO main.\"" + table + "\"(" +
                        list + ") SELECT " + list + " FROM src.\"" + table + "\"")
                    .ok())
        << table;
  }
  ASSERT_TRUE(db.Exec("PRAGMA foreign_keys = ON").ok());
  ASSERT_TRUE(db.Exec("DETACH DATABASE src").ok());
}

TEST_F(GpkgCliTest, AnOlderStoreOpensAsAGeoPackageOnceMigrated) {
  const std::string old = dir_->Path("old.tinbase");
  {
    // A store as migration 0012 left it, holding the rows of store_ (the columns it had then):
    // the header and meta written before migration 0013.
    auto db = Connection::Open(old, Connection::Mode::kCreate);
    ASSERT_TRUE(db.ok()) << db.status().ToString();
    ASSERT_TRUE(
        (*db)->Exec("PRAGMA application_id = " + std::to_string(kTinbaseApplicationId)).ok());
    ASSERT_TRUE(MigrateStore(**db, 12).ok());
    CopyRowsOfOlderSchema(**db, store_);
    ASSERT_TRUE((*db)
                    ->Exec("PRAGMA application_id = " + std::to_string(kTinbaseApplicationId) +
                           "; DELETE FROM meta WHERE key = 'application'")
                    .ok());
  }
  auto before = RunTool("ogrinfo -ro " + Quote(old));
  EXPECT_EQ(before.out.find("using driver `GPKG'"), std::string::npos) << before.out;
  { ASSERT_TRUE(Store::Open(old, Store::Access::kReadWrite).ok()); }
  auto after = RunTool("ogrinfo -ro -so " + Quote(old) + " tinbase_triangles");
  ASSERT_EQ(after.exit_code, 0) << after.out;
  EXPECT_NE(after.out.find("using driver `GPKG'"), std::string::npos) << after.out;
  EXPECT_EQ(ValueAfter(after.out, "Feature Count: "),
            ValueAfter(RunTool("ogrinfo -ro -so " + Quote(store_) + " tinbase_triangles").out,
                       "Feature Count: "));
  EXPECT_EQ(RunCli("check " + Quote(old)).exit_code, 0);
}

TEST_F(GpkgCliTest, AnotherProgramsGeoPackageIsNotAStore) {
  const std::string other = dir_->Path("other.gpkg");
  {
    auto db = Connection::Open(other, Connection::Mode::kCreate);
    ASSERT_TRUE(db.ok()) << db.status().ToString();
    // GeoPackage 1.1's application_id, as a store's, without the store's meta row.
    ASSERT_TRUE((*db)
                    ->Exec("PRAGMA application_id = 1196437809; CREATE TABLE meta(key TEXT "
                           "PRIMARY KEY, value TEXT)")
                    .ok());
  }
  const CliResult r = RunCli("info " + Quote(other));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("is not a tinbase store (a GeoPackage of another program)"),
            std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace tinbase
