// A store spread over two PostgreSQL servers with postgres_fdw (issue 27, "past one machine";
// docs/scaling.md). Two throwaway servers (scripts/pg-server.sh): the coordinator holds the store;
// its `triangles` table is turned into one partitioned by range of block, the southern band a
// local partition, the northern band a foreign table on the shard server. The CLI then works on
// the coordinator as on any store: locate, neighbours and `check --full` give what they give on
// an SQLite store built the same way, a polygon insert lands rows on both servers and leaves the
// same surface as on SQLite, and a rolled-back write leaves neither server changed.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "db/sql/connection.h"
#include "tests/support/cli_support.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {
namespace {

const std::string kServerScript = std::string(TINBASE_SCHEMA_DIR) + "/../scripts/pg-server.sh";

// The standard output of the shell command `command`, its trailing newline cut; "" on failure.
std::string Output(const std::string& command) {
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  if (pipe == nullptr) return "";
  std::string out;
  char buffer[256];
  while (fgets(buffer, sizeof buffer, pipe.get()) != nullptr) out += buffer;
  while (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

// A throwaway server in `dir`, stopped and removed when the object dies.
class Server {
 public:
  explicit Server(std::string dir) : dir_(std::move(dir)) {
    url_ = Output(kServerScript + " start " + Quote(dir_));
  }
  ~Server() { (void)std::system((kServerScript + " stop " + Quote(dir_)).c_str()); }
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;
  const std::string& url() const { return url_; }
  // The port of its URL (postgresql://user@127.0.0.1:PORT/db).
  std::string Port() const {
    const size_t colon = url_.rfind(':');
    return url_.substr(colon + 1, url_.find('/', colon) - colon - 1);
  }

 private:
  std::string dir_;
  std::string url_;
};

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::unique_ptr<Connection> Connect(const std::string& target) {
  auto db = Connection::Open(target, Connection::Mode::kReadWrite);
  EXPECT_TRUE(db.ok()) << target << ": " << db.status().ToString();
  return db.ok() ? std::move(*db) : nullptr;
}

int64_t Int(Connection& db, const std::string& sql) {
  auto value = db.QueryInt(sql);
  EXPECT_TRUE(value.ok()) << sql << ": " << value.status().ToString();
  return value.ok() ? *value : -1;
}

void Exec(Connection& db, const std::string& sql) {
  const Status s = db.Exec(sql);
  ASSERT_TRUE(s.ok()) << sql << "\n" << s.ToString();
}

void BuildTerrain(const std::string& store) {
  RunWrite(store, "init " + Quote(store));
  RunWrite(store,
           "dem import " + Quote(store) + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
  RunWrite(store, "tin build " + Quote(store) + " --surface terrain --tolerance 10");
}

// Turns the coordinator store's `triangles` into a table partitioned by range of block: blocks
// below the median one in a local partition, the others in triangles_far on the shard (schema
// `terrain` there). The views over triangles are made again; ids, trigger and indexes stay as the
// schema has them, but for the unique index on id, which PostgreSQL allows only per partition
// (and the shard's table has its own primary key). One transaction on the coordinator.
void Spread(Connection& coordinator, Connection& shard, const std::string& shard_port) {
  auto columns = coordinator.Prepare(
      "SELECT string_agg(quote_ident(attname) || ' ' || format_type(atttypid, atttypmod) || "
      "CASE WHEN attnotnull THEN ' NOT NULL' ELSE '' END, ', ' ORDER BY attnum) "
      "FROM pg_attribute WHERE attrelid = 'triangles'::regclass AND attnum > 0 AND NOT "
      "attisdropped");
  ASSERT_TRUE(columns.ok() && *(*columns)->Step());
  Exec(shard, "CREATE SCHEMA terrain; CREATE TABLE terrain.triangles_far(" +
                  (*columns)->ColumnText(0) +
                  ", PRIMARY KEY (id)); CREATE INDEX ON terrain.triangles_far(surface, block)");

  auto views = coordinator.Prepare(
      "SELECT DISTINCT v.relname, pg_get_viewdef(v.oid) FROM pg_depend d "
      "JOIN pg_rewrite r ON r.oid = d.objid JOIN pg_class v ON v.oid = r.ev_class "
      "WHERE d.refobjid = 'triangles'::regclass AND v.oid <> d.refobjid");
  ASSERT_TRUE(views.ok());
  std::vector<std::pair<std::string, std::string>> definitions;
  while (*(*views)->Step())
    definitions.emplace_back((*views)->ColumnText(0), (*views)->ColumnText(1));
  ASSERT_FALSE(definitions.empty());
  const int64_t split =
      Int(coordinator, "SELECT percentile_disc(0.5) WITHIN GROUP (ORDER BY block) FROM triangles");

  std::string sql =
      "BEGIN;\n"
      "CREATE EXTENSION IF NOT EXISTS postgres_fdw SCHEMA public;\n"
      "CREATE SERVER shard FOREIGN DATA WRAPPER postgres_fdw OPTIONS (host '127.0.0.1', port '" +
      shard_port +
      "', dbname 'tinbase');\n"
      "CREATE USER MAPPING FOR CURRENT_USER SERVER shard OPTIONS (user 'tinbase');\n";
  for (const auto& [name, definition] : definitions) sql += "DROP VIEW " + name + ";\n";
  sql +=
      "ALTER TABLE triangles RENAME TO triangles_whole;\n"
      "CREATE TABLE triangles (LIKE triangles_whole INCLUDING DEFAULTS INCLUDING CONSTRAINTS) "
      "PARTITION BY RANGE (block);\n"
      "CREATE TABLE triangles_near PARTITION OF triangles FOR VALUES FROM (MINVALUE) TO (" +
      std::to_string(split) +
      ");\n"
      "CREATE FOREIGN TABLE triangles_far PARTITION OF triangles FOR VALUES FROM (" +
      std::to_string(split) +
      ") TO (MAXVALUE) SERVER shard OPTIONS (schema_name 'terrain', table_name "
      "'triangles_far');\n"
      "INSERT INTO triangles SELECT * FROM triangles_whole;\n"
      "DROP TABLE triangles_whole;\n"
      "CREATE UNIQUE INDEX triangles_near_id ON triangles_near(id);\n"
      "CREATE INDEX triangles_surface_block ON triangles(surface, block);\n"
      "CREATE TRIGGER triangles_id BEFORE INSERT ON triangles FOR EACH ROW EXECUTE FUNCTION "
      "tinbase_triangles_id();\n";
  for (const auto& [name, definition] : definitions)
    sql += "CREATE VIEW " + name + " AS " + definition + "\n";
  sql += "COMMIT;";
  Exec(coordinator, sql);
}

// Points over the DEM's box and a margin around it (some fall outside the surface), as x,y text.
std::string PointsFile(const TempDir& dir) {
  std::mt19937 rng(27);
  std::uniform_real_distribution<double> x(505000, 575000), y(7462000, 7532000);
  const std::string path = dir.Path("points.txt");
  std::ofstream out(path);
  out.precision(17);
  for (int i = 0; i < 300; ++i) out << x(rng) << "," << y(rng) << "\n";
  return path;
}

// Three 2 km squares from south to north through the DEM's centre (EPSG:28350), tagged s0..s2.
std::string Squares(const TempDir& dir) {
  const std::string path = dir.Path("squares.geojson");
  std::ofstream out(path);
  out.precision(17);
  out << R"({"type":"FeatureCollection","crs":{"type":"name","properties":{"name":"EPSG:28350"}},)"
      << R"("features":[)";
  for (int k = 0; k < 3; ++k) {
    const double x = 537298 + 1500 * k, y = 7480339 + 14000 * k;
    out << (k == 0 ? "" : ",") << R"({"type":"Feature","properties":{"tag":"s)" << k
        << R"("},"geometry":{"type":"Polygon","coordinates":[[[)" << x << "," << y << "],["
        << x + 2000 << "," << y << "],[" << x + 2000 << "," << y + 2000 << "],[" << x << ","
        << y + 2000 << "],[" << x << "," << y << "]]]}}";
  }
  out << "]}";
  return path;
}

// The output of the same query command on both stores must be equal; returns it.
std::string SameAnswer(const std::string& spread, const std::string& sqlite,
                       const std::string& command, const std::string& rest) {
  const CliResult a = RunCli(command + " " + Quote(spread) + " " + rest);
  const CliResult b = RunCli(command + " " + Quote(sqlite) + " " + rest);
  EXPECT_EQ(a.exit_code, 0) << command << " " << rest << ": " << a.err;
  EXPECT_EQ(b.exit_code, 0) << command << " " << rest << ": " << b.err;
  EXPECT_EQ(a.out, b.out) << command << " " << rest;
  return a.out;
}

TEST(FdwPartitionsTest, TrianglesOverTwoServersAnswerAndEditAsOneStore) {
  TempDir dir;
  ASSERT_EQ(chmod(dir.dir().c_str(), 0755), 0);  // the servers may run as the postgres user
  const Server coordinator(dir.Path("coordinator"));
  const Server shard_server(dir.Path("shard"));
  ASSERT_FALSE(coordinator.url().empty()) << "the coordinator server did not start";
  ASSERT_FALSE(shard_server.url().empty()) << "the shard server did not start";
  const std::string store = coordinator.url() + "?schema=terrain";
  const std::string sqlite = dir.Path("whole.tinbase");
  BuildTerrain(store);
  BuildTerrain(sqlite);

  std::unique_ptr<Connection> db = Connect(store);
  std::unique_ptr<Connection> shard = Connect(shard_server.url() + "?schema=public");
  ASSERT_TRUE(db != nullptr && shard != nullptr);
  const int64_t triangles = Int(*db, "SELECT count(*) FROM triangles");
  Spread(*db, *shard, shard_server.Port());
  if (::testing::Test::HasFatalFailure()) return;

  // Both servers hold part of the mesh, and the coordinator sees it whole.
  const int64_t far = Int(*shard, "SELECT count(*) FROM terrain.triangles_far");
  const int64_t near = Int(*db, "SELECT count(*) FROM ONLY triangles_near");
  EXPECT_GT(far, 0);
  EXPECT_GT(near, 0);
  EXPECT_EQ(far + near, triangles);
  EXPECT_EQ(Int(*db, "SELECT count(*) FROM triangles"), triangles);
  EXPECT_EQ(Int(*db, "SELECT relkind = 'p' FROM pg_class WHERE oid = 'triangles'::regclass"), 1);

  // Queries through the coordinator: the same answers as the whole SQLite store.
  const CliResult check = RunCli("check --full " + Quote(store));
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  SameAnswer(store, sqlite, "locate", "--surface terrain --points " + Quote(PointsFile(dir)));
  for (const char* partition : {"triangles_near", "triangles_far"}) {
    const int64_t id = Int(*db, std::string("SELECT min(id) FROM ") + partition);
    SameAnswer(store, sqlite, "neighbours", "--surface terrain --json " + std::to_string(id));
  }

  // An insert through the coordinator: its rows land on both servers in one transaction, and the
  // surface equals the SQLite store's after the same insert.
  const int64_t far_max = Int(*shard, "SELECT max(id) FROM terrain.triangles_far");
  const int64_t near_max = Int(*db, "SELECT max(id) FROM ONLY triangles_near");
  const std::string squares = Squares(dir);
  for (const std::string& target : {store, sqlite})
    RunWrite(target, "polygon add " + Quote(target) + " " + Quote(squares) +
                         " --surface terrain --mode fill --tag-field tag");
  EXPECT_GT(Int(*shard, "SELECT max(id) FROM terrain.triangles_far"), far_max);
  EXPECT_GT(Int(*db, "SELECT max(id) FROM ONLY triangles_near"), near_max);
  for (const auto& [target, name] : {std::pair{sqlite, "s.obj"}, std::pair{store, "p.obj"}})
    ASSERT_EQ(RunCli("export " + Quote(target) + " --surface terrain -o " + Quote(dir.Path(name)))
                  .exit_code,
              0);
  EXPECT_EQ(ReadAll(dir.Path("p.obj")), ReadAll(dir.Path("s.obj")));
  SameAnswer(store, sqlite, "locate", "--surface terrain --points " + Quote(PointsFile(dir)));

  // A write of rows on both servers, rolled back on the coordinator, leaves both as they were
  // (postgres_fdw ends its remote transaction with the local one).
  const auto before = TableChecksums(store);
  const int64_t far_rows = Int(*shard, "SELECT count(*) FROM terrain.triangles_far");
  Exec(*db,
       "BEGIN; DELETE FROM triangles WHERE id IN (SELECT min(id) FROM triangles_near UNION ALL "
       "SELECT min(id) FROM triangles_far); ROLLBACK");
  EXPECT_EQ(Int(*shard, "SELECT count(*) FROM terrain.triangles_far"), far_rows);
  EXPECT_EQ(TableChecksums(store), before);
}

}  // namespace
}  // namespace tinbase::testing
