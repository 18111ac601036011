// SQL injection attempts through the values a user gives a PostgreSQL store (a surface name, tags,
// feature attributes and names) are stored as text, never run: every table is still there,
// `check --full` passes, and each hostile text reads back exactly. (The schema parameter of the
// URL is refused outright: tests/apps/postgres_cli_test.cc.)
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "db/sql/connection.h"
#include "tests/support/cli_support.h"
#include "tests/support/postgres_support.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {
namespace {

// A shell word holding `text` (which may contain single quotes).
std::string ShellWord(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

TEST(PgInjectionTest, HostileNamesTagsAndAttributesAreStoredAsText) {
  TempDir dir;
  const std::string store = FreshPostgresStore("inject");
  ASSERT_FALSE(store.empty());
  const std::string surface = "t'); DROP TABLE triangles; --";
  const std::string tag = "u'; DELETE FROM features; SELECT '";
  const std::string note = "\"; DROP SCHEMA public CASCADE; --'";
  RunWrite(store, "init " + Quote(store));
  RunWrite(store,
           "dem import " + Quote(store) + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
  RunWrite(store,
           "tin build " + Quote(store) + " --surface " + ShellWord(surface) + " --tolerance 10");

  const nlohmann::json features = {
      {"type", "FeatureCollection"},
      {"crs", {{"type", "name"}, {"properties", {{"name", "EPSG:28350"}}}}},
      {"features",
       {{{"type", "Feature"},
         {"properties", {{"unit", tag}, {"note", note}, {"name", surface}}},
         {"geometry",
          {{"type", "Polygon"},
           {"coordinates",
            {{{530000, 7490000}, {534000, 7490000}, {534000, 7494000}, {530000, 7490000}}}}}}}}}};
  const std::string file = dir.Path("hostile.geojson");
  std::ofstream(file) << features.dump();
  RunWrite(store, "polygon add " + Quote(store) + " " + Quote(file) + " --surface " +
                      ShellWord(surface) + " --mode fill --tag-field unit");

  auto db = Connection::Open(store, Connection::Mode::kReadOnly);
  ASSERT_TRUE(db.ok()) << db.status().ToString();
  EXPECT_GT(*(*db)->QueryInt("SELECT count(*) FROM triangles"), 0);
  EXPECT_EQ(*(*db)->QueryInt("SELECT count(*) FROM features"), 1);
  EXPECT_EQ(*(*db)->QueryInt("SELECT count(*) FROM pg_namespace WHERE nspname = 'public'"), 1);
  auto read = (*db)->Prepare(
      "SELECT s.name, g.value, f.attributes FROM features f JOIN surfaces s ON s.id = f.surface "
      "JOIN tags g ON g.id = f.tag");
  ASSERT_TRUE(read.ok());
  ASSERT_TRUE(*(*read)->Step());
  EXPECT_EQ((*read)->ColumnText(0), surface);
  EXPECT_EQ((*read)->ColumnText(1), tag);
  const nlohmann::json attributes = nlohmann::json::parse((*read)->ColumnText(2));
  EXPECT_EQ(attributes.value("note", ""), note) << attributes.dump();

  // The hostile surface name also works as a name where the CLI looks a surface up.
  const nlohmann::json info = Json(RunCli("info --json " + Quote(store)));
  EXPECT_EQ(info["surfaces"][0]["name"], surface);
  CliResult located = RunCli("locate --json " + Quote(store) + " --surface " + ShellWord(surface) +
                             " -- 532000 7491000");
  EXPECT_EQ(located.exit_code, 0) << located.err;
}

}  // namespace
}  // namespace tinbase::testing
