// The CLI on a PostgreSQL store: the same commands build, edit, check and query the same surface
// as on an SQLite file, and a PostgreSQL store is one schema of a database.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "tests/support/cli_support.h"
#include "tests/support/gdal_tools.h"
#include "tests/support/postgres_support.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {
namespace {

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Builds the Hamersley surface with its geology in `store`, as CliTest does on SQLite.
void BuildHamersley(const std::string& store) {
  RunWrite(store, "init " + Quote(store));
  RunWrite(store,
           "dem import " + Quote(store) + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
  RunWrite(store, "tin build " + Quote(store) + " --surface terrain --tolerance 10");
  RunWrite(store, "polygon add " + Quote(store) + " " +
                      Quote(DataPath("geology/hamersley/geology.geojson")) +
                      " --surface terrain --mode fill --tag-field unitname");
}

nlohmann::json SurfaceCounts(const std::string& store) {
  nlohmann::json info = Json(RunCli("info --json " + Quote(store)));
  nlohmann::json surface = info["surfaces"][0];
  return {surface["vertices"], surface["triangles"], surface["visible_triangles"],
          surface["constraints"], surface["features"]};
}

TEST(PostgresCliTest, TheSameCommandsMakeTheSameSurfaceAsOnSqlite) {
  TempDir dir;
  const std::string sqlite = dir.Path("s.tinbase");
  const std::string postgres = FreshPostgresStore("cli");
  ASSERT_FALSE(postgres.empty());
  BuildHamersley(sqlite);
  BuildHamersley(postgres);
  EXPECT_EQ(SurfaceCounts(postgres), SurfaceCounts(sqlite));

  // The same surface, vertex for vertex and triangle for triangle: the OBJ exports are equal.
  for (const auto& [store, name] : {std::pair{sqlite, "s.obj"}, std::pair{postgres, "p.obj"}})
    ASSERT_EQ(RunCli("export " + Quote(store) + " --surface terrain -o " + Quote(dir.Path(name)))
                  .exit_code,
              0);
  EXPECT_EQ(ReadAll(dir.Path("p.obj")), ReadAll(dir.Path("s.obj")));

  // Point location finds the same triangle (the walk may start elsewhere: "steps" may differ).
  const nlohmann::json info = Json(RunCli("info --json " + Quote(sqlite)));
  const auto& bbox = info["dems"][0]["bbox"];
  const std::string point = std::to_string((bbox[0].get<double>() + bbox[2].get<double>()) / 2) +
                            " " +
                            std::to_string((bbox[1].get<double>() + bbox[3].get<double>()) / 2);
  nlohmann::json on_postgres =
      Json(RunCli("locate --json " + Quote(postgres) + " --surface terrain -- " + point));
  nlohmann::json on_sqlite =
      Json(RunCli("locate --json " + Quote(sqlite) + " --surface terrain -- " + point));
  on_postgres.erase("steps");
  on_sqlite.erase("steps");
  EXPECT_EQ(on_postgres, on_sqlite);

  // psql and ogrinfo see the surface and the map as PostGIS layers of the store's schema.
  const std::string schema = postgres.substr(postgres.find("?schema=") + 8);
  const std::string url = postgres.substr(0, postgres.find('?'));
  ASSERT_TRUE(HaveTool("psql", "postgresql-client-15"));
  const ToolResult counted = RunTool(
      "psql " + Quote(url) + " -qXAt -v ON_ERROR_STOP=1 -c " +
      Quote("SET search_path TO " + schema +
            ", public; SELECT count(*) || chr(32) || min(ST_NPoints(geom)) || chr(32) || "
            "max(ST_SRID(geom)) FROM tinbase_triangles; SELECT count(*) FROM tinbase_features"));
  ASSERT_EQ(counted.exit_code, 0) << counted.out;
  EXPECT_EQ(counted.out, SurfaceCounts(sqlite)[1].dump() + " 4 28350\n61\n");
  ASSERT_TRUE(HaveTool("ogrinfo"));
  const ToolResult layer = RunTool("ogrinfo -ro -so " + Quote("PG:" + url) +
                                   " -oo ACTIVE_SCHEMA=" + schema + " tinbase_features");
  ASSERT_EQ(layer.exit_code, 0) << layer.out;
  EXPECT_EQ(ValueAfter(layer.out, "Feature Count: "), "61") << layer.out;

  // A removal is local and transactional there too.
  RunWrite(sqlite, "polygon remove " + Quote(sqlite) + " 7");
  RunWrite(postgres, "polygon remove " + Quote(postgres) + " 7");
  EXPECT_EQ(SurfaceCounts(postgres), SurfaceCounts(sqlite));
}

TEST(PostgresCliTest, StoresAreSchemasAndBadTargetsAreNamed) {
  const std::string url = PostgresUrl();
  ASSERT_FALSE(url.empty());
  const std::string store = FreshPostgresStore("schemas");
  RunWrite(store, "init " + Quote(store) + " --crs EPSG:28350");
  // A second init of the same schema is refused; another schema is another store.
  CliResult again = RunCli("init " + Quote(store));
  EXPECT_NE(again.exit_code, 0);
  EXPECT_NE(again.err.find("a store already exists there"), std::string::npos) << again.err;
  CliResult absent = RunCli("info " + Quote(url + "?schema=no_such_schema_here"));
  EXPECT_NE(absent.exit_code, 0);
  EXPECT_NE(absent.err.find("schema 'no_such_schema_here' does not exist"), std::string::npos)
      << absent.err;
  CliResult injected = RunCli("info " + Quote(url + "?schema=x;DROP SCHEMA public"));
  EXPECT_NE(injected.exit_code, 0);
  EXPECT_NE(injected.err.find("is not a plain lower-case name"), std::string::npos) << injected.err;
  // A refused connection names the server and says why, without a password.
  CliResult refused = RunCli("info 'postgresql://ann:secret@127.0.0.1:1/x'");
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.err.find("cannot connect"), std::string::npos) << refused.err;
  EXPECT_EQ(refused.err.find("secret"), std::string::npos) << refused.err;
}

}  // namespace
}  // namespace tinbase::testing
