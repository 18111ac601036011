// libtinbase_sqlite in the real sqlite3 shell: a store made by the CLI, `.load`ed, queried in SQL.
// Each SQL function must agree with the CLI command it mirrors (`locate --points --json`,
// `neighbours --json`, `check --json`, `profile --json`), answer NULL outside the surface, and
// refuse bad arguments with one error naming the function and the argument.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/cli_support.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::CliResult;
using testing::DataPath;
using testing::Json;
using testing::Quote;
using testing::RunCli;
using testing::TempDir;

struct ShellResult {
  int exit_code = 0;
  std::string out;
  std::string err;
};

std::string Slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Runs `sql` in the sqlite3 shell on `database` after `.load`ing the extension (by its path
// without the ".so", as a user types it), in JSON output mode, stopping at the first error.
ShellResult RunSqlite(const std::string& database, const std::string& sql) {
  TempDir tmp;
  const std::string script = tmp.Path("script.sql");
  std::ofstream(script) << sql << "\n";
  std::string extension = TINBASE_SQLITE_EXTENSION;
  extension.erase(extension.size() - 3);  // ".so"
  const std::string command = "sqlite3 -bail -json -cmd " + Quote(".load " + extension) + " " +
                              Quote(database) + " <" + Quote(script) + " >" +
                              Quote(tmp.Path("out")) + " 2>" + Quote(tmp.Path("err"));
  const int status = std::system(command.c_str());
  ShellResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  result.out = Slurp(tmp.Path("out"));
  result.err = Slurp(tmp.Path("err"));
  return result;
}

// The rows a successful query printed (an empty result prints nothing).
nlohmann::json Rows(const ShellResult& r) {
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  if (r.out.empty()) return nlohmann::json::array();
  return nlohmann::json::parse(r.out);
}

// One value: the first column of the first row.
nlohmann::json Value(const ShellResult& r) {
  nlohmann::json rows = Rows(r);
  if (rows.empty()) return nullptr;
  return rows[0].begin().value();
}

std::string Number(double v) {
  std::ostringstream out;
  out.precision(17);
  out << v;
  return out.str();
}

class SqliteExtensionTest : public ::testing::Test {
 protected:
  // One store for the suite: the Hamersley DEM, surface `terrain` at 10 m, and a square tagged
  // `granite` around the map's centre (the functions only read it).
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    store_ = dir_->Path("s.tinbase");
    testing::RunWrite(store_, "init " + Quote(store_));
    testing::RunWrite(store_, "dem import " + Quote(store_) + " " +
                                  Quote(DataPath("geology/hamersley/dtm_rp.tif")));
    testing::RunWrite(store_, "tin build " + Quote(store_) + " --surface terrain --tolerance 10");
    const auto info = Json(RunCli("info --json " + Quote(store_)));
    for (int i = 0; i < 4; ++i) bbox_[i] = info["dems"][0]["bbox"][i].get<double>();
    const double x = (bbox_[0] + bbox_[2]) / 2;
    const double y = (bbox_[1] + bbox_[3]) / 2;
    const std::string square = dir_->Path("square.geojson");
    std::ofstream(square) << R"({"type":"FeatureCollection","crs":{"type":"name","properties":)"
                          << R"({"name":"EPSG:28350"}},"features":[{"type":"Feature",)"
                          << R"("properties":{},"geometry":{"type":"Polygon","coordinates":[[)"
                          << "[" << x - 2000 << "," << y - 2000 << "],[" << x + 2000 << ","
                          << y - 2000 << "],[" << x + 2000 << "," << y + 2000 << "],[" << x - 2000
                          << "," << y + 2000 << "],[" << x - 2000 << "," << y - 2000 << "]]]}}]}";
    testing::RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(square) +
                                  " --surface terrain --mode fill --tag granite");
  }
  static void TearDownTestSuite() { delete dir_; }

  static std::string Z(const std::string& x, const std::string& y) {
    return "SELECT tinbase_z('terrain', " + x + ", " + y + ") AS v;";
  }
  // A bad call: the shell fails with one message that names the function and says `expected`.
  static void ExpectSqlError(const std::string& sql, const std::string& expected,
                             const std::string& database = store_) {
    const ShellResult r = RunSqlite(database, sql);
    EXPECT_NE(r.exit_code, 0) << sql;
    EXPECT_NE(r.err.find(expected), std::string::npos) << sql << "\nstderr: " << r.err;
  }

  static TempDir* dir_;
  static std::string store_;
  static double bbox_[4];
};

TempDir* SqliteExtensionTest::dir_ = nullptr;
std::string SqliteExtensionTest::store_;
double SqliteExtensionTest::bbox_[4] = {};

// A table of wells, some outside: tinbase_z and tinbase_locate give `locate --points --json`'s z
// and triangle for each, NULL for those outside. The wells run in sorted order, so the locator
// walks from one answer to the next.
TEST_F(SqliteExtensionTest, ZAndLocateAgreeWithTheCliAndAreNullOutside) {
  std::vector<std::pair<double, double>> wells;
  for (int i = 0; i < 60; ++i) {
    wells.emplace_back(bbox_[0] + (bbox_[2] - bbox_[0]) * (i + 0.37) / 60.3,
                       bbox_[1] + (bbox_[3] - bbox_[1]) * (i * 7 % 60 + 0.61) / 60.7);
  }
  wells.emplace_back(bbox_[0] - 5000, bbox_[1] + 10);  // outside, west
  wells.emplace_back(bbox_[2] + 1, bbox_[3] + 1);      // outside, north-east
  const std::string points = dir_->Path("wells.csv");
  std::string sql = "CREATE TEMP TABLE wells(id INTEGER PRIMARY KEY, x REAL, y REAL);\n";
  {
    std::ofstream csv(points);
    for (size_t i = 0; i < wells.size(); ++i) {
      csv << Number(wells[i].first) << "," << Number(wells[i].second) << "\n";
      sql += "INSERT INTO wells VALUES (" + std::to_string(i) + ", " + Number(wells[i].first) +
             ", " + Number(wells[i].second) + ");\n";
    }
  }
  sql +=
      "SELECT id, tinbase_z('terrain', x, y) AS z, tinbase_locate('terrain', x, y) AS triangle, "
      "tinbase_tag('terrain', x, y) AS tag FROM wells ORDER BY id;";
  const nlohmann::json rows = Rows(RunSqlite(store_, sql));
  const CliResult cli =
      RunCli("locate --json " + Quote(store_) + " --surface terrain --points " + Quote(points));
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  std::istringstream lines(cli.out);
  std::string line;
  size_t i = 0;
  int outside = 0;
  while (std::getline(lines, line)) {
    ASSERT_LT(i, rows.size());
    const auto want = nlohmann::json::parse(line);
    const auto& got = rows[i];
    SCOPED_TRACE("well " + std::to_string(i) + ": " + line);
    EXPECT_EQ(got["id"], i);
    if (want["triangle"].is_null()) {
      ++outside;
      EXPECT_TRUE(got["z"].is_null());
      EXPECT_TRUE(got["triangle"].is_null());
      EXPECT_TRUE(got["tag"].is_null());
    } else {
      EXPECT_EQ(got["triangle"], want["triangle"]);
      // The shell prints reals to 15 digits; z is in metres, a few hundred of them.
      EXPECT_NEAR(got["z"].get<double>(), want["z"].get<double>(), 1e-9);
      EXPECT_EQ(got["tag"], want["tag"]);
    }
    ++i;
  }
  EXPECT_EQ(i, wells.size());
  EXPECT_EQ(outside, 2);
}

TEST_F(SqliteExtensionTest, TagIsTheFillPolygonsTag) {
  const std::string x = Number((bbox_[0] + bbox_[2]) / 2);
  const std::string y = Number((bbox_[1] + bbox_[3]) / 2);
  EXPECT_EQ(Value(RunSqlite(store_, "SELECT tinbase_tag('terrain', " + x + ", " + y + ") AS v;")),
            "granite");
  const std::string corner_x = Number(bbox_[0] + 100);
  const std::string corner_y = Number(bbox_[1] + 100);
  EXPECT_TRUE(Value(RunSqlite(store_, "SELECT tinbase_tag('terrain', " + corner_x + ", " +
                                          corner_y + ") AS v;"))
                  .is_null());
}

TEST_F(SqliteExtensionTest, NullCoordinatesGiveNull) {
  EXPECT_TRUE(Value(RunSqlite(store_, Z("NULL", "1"))).is_null());
  EXPECT_TRUE(
      Value(RunSqlite(store_, "SELECT tinbase_locate('terrain', 1, NULL) AS v;")).is_null());
}

TEST_F(SqliteExtensionTest, NeighboursAreTheClis) {
  const std::string x = Number(bbox_[0] + (bbox_[2] - bbox_[0]) / 3);
  const std::string y = Number((bbox_[1] + bbox_[3]) / 2);
  const ShellResult r =
      RunSqlite(store_,
                "SELECT t, tinbase_neighbours('terrain', t) AS n FROM (SELECT tinbase_locate("
                "'terrain', " +
                    x + ", " + y + ") AS t);");
  const nlohmann::json rows = Rows(r);
  ASSERT_EQ(rows.size(), 1u);
  const int64_t triangle = rows[0]["t"].get<int64_t>();
  const auto want = Json(RunCli("neighbours --json " + Quote(store_) + " --surface terrain " +
                                std::to_string(triangle)));
  EXPECT_EQ(nlohmann::json::parse(rows[0]["n"].get<std::string>()), want["neighbours"]);
}

TEST_F(SqliteExtensionTest, CheckIsTheClis) {
  const nlohmann::json got = nlohmann::json::parse(
      Value(RunSqlite(store_, "SELECT tinbase_check('terrain') AS v;")).get<std::string>());
  EXPECT_EQ(got, Json(RunCli("check --json --surface terrain " + Quote(store_))));
  EXPECT_TRUE(got["ok"].get<bool>());
  const nlohmann::json full = nlohmann::json::parse(
      Value(RunSqlite(store_, "SELECT tinbase_check('terrain', 1) AS v;")).get<std::string>());
  EXPECT_EQ(full, Json(RunCli("check --json --full --surface terrain " + Quote(store_))));
}

TEST_F(SqliteExtensionTest, ProfileIsTheClisInWktOrPointList) {
  const double x0 = bbox_[0] + (bbox_[2] - bbox_[0]) * 0.21;
  const double y0 = bbox_[1] + (bbox_[3] - bbox_[1]) * 0.33;
  const double x1 = bbox_[0] + (bbox_[2] - bbox_[0]) * 0.74;
  const double y1 = bbox_[1] + (bbox_[3] - bbox_[1]) * 0.58;
  const std::string list = Number(x0) + "," + Number(y0) + " " + Number(x1) + "," + Number(y1);
  const std::string wkt =
      "LINESTRING (" + Number(x0) + " " + Number(y0) + ", " + Number(x1) + " " + Number(y1) + ")";
  const auto want =
      Json(RunCli("profile --json " + Quote(store_) + " --surface terrain --line " + Quote(list)));
  for (const std::string& line : {list, wkt}) {
    SCOPED_TRACE(line);
    const nlohmann::json got = nlohmann::json::parse(
        Value(RunSqlite(store_, "SELECT tinbase_profile('terrain', '" + line + "') AS v;"))
            .get<std::string>());
    EXPECT_EQ(got, want);
  }
}

// Any client loads it with load_extension(), by its default entry point or by its own name.
TEST_F(SqliteExtensionTest, LoadExtensionFromSql) {
  std::string extension = TINBASE_SQLITE_EXTENSION;
  const std::string x = Number((bbox_[0] + bbox_[2]) / 2);
  const std::string y = Number((bbox_[1] + bbox_[3]) / 2);
  const std::string z = "SELECT tinbase_z('terrain', " + x + ", " + y + ") AS v;";
  const double want = Value(RunSqlite(store_, z)).get<double>();
  for (const std::string& load :
       {"SELECT load_extension('" + extension + "');",
        "SELECT load_extension('" + extension + "', 'sqlite3_tinbase_sqlite_init');"}) {
    SCOPED_TRACE(load);
    TempDir tmp;
    const std::string script = tmp.Path("script.sql");
    std::ofstream(script) << ".output /dev/null\n" << load << "\n.output stdout\n" << z << "\n";
    const std::string command = "sqlite3 -bail -json " + Quote(store_) + " <" + Quote(script) +
                                " >" + Quote(tmp.Path("out")) + " 2>" + Quote(tmp.Path("err"));
    ASSERT_EQ(std::system(command.c_str()), 0) << Slurp(tmp.Path("err"));
    const nlohmann::json rows = nlohmann::json::parse(Slurp(tmp.Path("out")));
    EXPECT_EQ(rows[0]["v"].get<double>(), want);
  }
}

// Every bad argument fails the statement with a message naming the function and the argument.
TEST_F(SqliteExtensionTest, BadSurfaceNameIsAnError) {
  ExpectSqlError("SELECT tinbase_z('nosuch', 1, 2);", "tinbase_z: no surface named 'nosuch'");
  ExpectSqlError("SELECT tinbase_locate(NULL, 1, 2);",
                 "tinbase_locate: argument 1 (surface) must be text, got NULL");
  ExpectSqlError("SELECT tinbase_neighbours('nosuch', 1);", "tinbase_neighbours: no surface named");
  ExpectSqlError("SELECT tinbase_check('nosuch');", "tinbase_check:");
  ExpectSqlError("SELECT tinbase_profile('nosuch', '0,0 1,1');", "tinbase_profile: no surface");
}

TEST_F(SqliteExtensionTest, NonNumericCoordinateIsAnError) {
  ExpectSqlError(Z("'abc'", "2"), "tinbase_z: argument 2 (x) must be a number, got text 'abc'");
  ExpectSqlError(Z("1", "X'00'"), "tinbase_z: argument 3 (y) must be a number, got a blob");
  ExpectSqlError("SELECT tinbase_tag('terrain', 1, '') AS v;",
                 "tinbase_tag: argument 3 (y) must be a number, got text ''");
}

TEST_F(SqliteExtensionTest, NonFiniteCoordinateIsAnError) {
  ExpectSqlError(Z("9e999", "2"), "tinbase_z: argument 2 (x) must be finite, got +Inf");
  ExpectSqlError("SELECT tinbase_locate('terrain', 1, -9e999) AS v;",
                 "tinbase_locate: argument 3 (y) must be finite, got -Inf");
}

TEST_F(SqliteExtensionTest, BadTriangleAndLineAreErrors) {
  ExpectSqlError("SELECT tinbase_neighbours('terrain', 'x');",
                 "tinbase_neighbours: argument 2 (triangle) must be an integer triangle id");
  ExpectSqlError("SELECT tinbase_neighbours('terrain', 999999999);",
                 "tinbase_neighbours: triangle 999999999");
  ExpectSqlError("SELECT tinbase_profile('terrain', 'LINESTRING (1 2)');",
                 "tinbase_profile: a profile line needs at least two points");
  ExpectSqlError("SELECT tinbase_profile('terrain', 'from here to there');",
                 "tinbase_profile: argument 2 (line)");
}

TEST_F(SqliteExtensionTest, ADatabaseThatIsNotAStoreIsAnError) {
  ExpectSqlError(Z("1", "2"), "tinbase_z: the main database is not a file", ":memory:");
  const std::string plain = dir_->Path("plain.sqlite");
  ASSERT_EQ(RunSqlite(plain, "CREATE TABLE t(x);").exit_code, 0);
  ExpectSqlError(Z("1", "2"), "tinbase_z: ", plain);
}

}  // namespace
}  // namespace tinbase
