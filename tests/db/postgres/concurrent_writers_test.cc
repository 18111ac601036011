// Four writer processes edit one PostgreSQL store at once for a minute (docs/scaling.md,
// "Writers"). Each runs `tinbase polygon add` again and again, one random polygon a command, all
// over the map, so their regions now lie apart and now overlap: edits of distant regions commit
// side by side, overlapping ones wait for each other's region locks and retry. Afterwards every
// command has succeeded, `check --full` passes, every committed feature is present, and the
// surface equals, by the exact local test (below), the one an SQLite store gets when the same
// features are added one by one in the order of their ids (a retried edit takes a new id, so of
// two edits that met, the one that committed last has the larger id; edits that never met
// commute).
// TINBASE_TEST_WRITERS_SECONDS shortens the minute for a quick run.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include "db/sql/connection.h"
#include "tests/support/cli_support.h"
#include "tests/support/postgres_support.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {
namespace {

constexpr int kWriters = 4;
constexpr double kCx = 539298, kCy = 7497339;  // the middle of the Hamersley DEM (EPSG:28350)

// A random convex polygon: 5 to 9 vertices on a circle of 300 to 1200 m about a point within
// 12 km of the middle, as a GeoJSON file of one feature.
std::string RandomPolygon(std::mt19937_64& random) {
  std::uniform_real_distribution<double> offset(-12000, 12000), radius(300, 1200), turn(0, 1);
  std::uniform_int_distribution<int> corners(5, 9);
  const double x = kCx + offset(random), y = kCy + offset(random), r = radius(random);
  const int n = corners(random);
  const double start = turn(random) * 2 * M_PI;
  std::ostringstream out;
  out.precision(17);
  out << R"({"type":"FeatureCollection","crs":{"type":"name","properties":{"name":"EPSG:28350"}},)"
      << R"("features":[{"type":"Feature","properties":{},"geometry":{"type":"Polygon",)"
      << R"("coordinates":[[)";
  for (int k = 0; k <= n; ++k) {
    const double a = start + 2 * M_PI * (k % n) / n;
    out << (k == 0 ? "" : ",") << "[" << x + r * std::cos(a) << "," << y + r * std::sin(a) << "]";
  }
  out << "]]}}]}";
  return out.str();
}

void BuildTerrain(const std::string& store) {
  RunWrite(store, "init " + Quote(store));
  RunWrite(store,
           "dem import " + Quote(store) + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
  RunWrite(store, "tin build " + Quote(store) + " --surface terrain --tolerance 10");
}

int Seconds() {
  const char* text = std::getenv("TINBASE_TEST_WRITERS_SECONDS");
  return text != nullptr && std::atoi(text) > 0 ? std::atoi(text) : 60;
}

std::string Text(double v) {
  std::ostringstream out;
  out.precision(17);
  out << v;
  return out.str();
}

// The surface `terrain` of `store` without its ids (which concurrent writers give out in another
// order): its vertices ("x y z kind") and constraints (their ends' coordinates, lower end first,
// and kind), both sorted; its number of triangles; and the plan area of its triangles by paint
// ("visible tag").
struct Surface {
  std::vector<std::string> vertices;
  std::vector<std::string> constraints;
  int64_t triangles = 0;
  std::map<std::string, double> area_by_paint;
};

std::vector<std::string> SortedRows(Connection& db, const std::string& sql,
                                    const std::function<std::string(Statement&)>& row_of) {
  std::vector<std::string> rows;
  auto stmt = db.Prepare(sql);
  EXPECT_TRUE(stmt.ok()) << stmt.status().ToString();
  if (!stmt.ok()) return rows;
  while (*(*stmt)->Step()) rows.push_back(row_of(**stmt));
  std::sort(rows.begin(), rows.end());
  return rows;
}

Surface Read(const std::string& store) {
  Surface out;
  auto db = Connection::Open(store, Connection::Mode::kReadOnly);
  EXPECT_TRUE(db.ok()) << db.status().ToString();
  if (!db.ok()) return out;
  const std::string terrain = " JOIN surfaces s ON s.id = t.surface WHERE s.name = 'terrain'";
  out.vertices =
      SortedRows(**db, "SELECT t.x, t.y, t.z, t.kind FROM vertices t" + terrain, [](Statement& r) {
        return Text(r.ColumnDouble(0)) + " " + Text(r.ColumnDouble(1)) + " " +
               Text(r.ColumnDouble(2)) + " " + r.ColumnText(3);
      });
  out.constraints = SortedRows(**db,
                               "SELECT a.x, a.y, a.z, b.x, b.y, b.z, t.kind FROM constraints t "
                               "JOIN vertices a ON a.id = t.va JOIN vertices b ON b.id = t.vb" +
                                   terrain,
                               [](Statement& r) {
                                 std::array<std::string, 2> ends;
                                 for (int e = 0; e < 2; ++e)
                                   ends[e] = Text(r.ColumnDouble(3 * e)) + " " +
                                             Text(r.ColumnDouble(3 * e + 1)) + " " +
                                             Text(r.ColumnDouble(3 * e + 2));
                                 std::sort(ends.begin(), ends.end());
                                 return ends[0] + " " + ends[1] + " " + r.ColumnText(6);
                               });
  auto triangles = (*db)->Prepare(
      "SELECT a.x, a.y, b.x, b.y, c.x, c.y, t.visible, coalesce(g.value, '') "
      "FROM triangles t JOIN vertices a ON a.id = t.v0 JOIN vertices b ON b.id = t.v1 "
      "JOIN vertices c ON c.id = t.v2 LEFT JOIN tags g ON g.id = t.tag" +
      terrain);
  EXPECT_TRUE(triangles.ok()) << triangles.status().ToString();
  if (!triangles.ok()) return out;
  while (*(*triangles)->Step()) {
    Statement& r = **triangles;
    const double area = 0.5 * std::fabs((r.ColumnDouble(2) - r.ColumnDouble(0)) *
                                            (r.ColumnDouble(5) - r.ColumnDouble(1)) -
                                        (r.ColumnDouble(4) - r.ColumnDouble(0)) *
                                            (r.ColumnDouble(3) - r.ColumnDouble(1)));
    out.area_by_paint[std::to_string(r.ColumnInt(6)) + " " + r.ColumnText(7)] += area;
    ++out.triangles;
  }
  return out;
}

// The first rows of `a` and `b` that only one of them holds.
std::string Difference(const std::vector<std::string>& a, const std::vector<std::string>& b) {
  std::vector<std::string> only;
  std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(only));
  std::string text;
  for (size_t k = 0; k < only.size() && k < 5; ++k) text += "\n  " + only[k];
  return text;
}

TEST(ConcurrentWritersTest, FourWritersForAMinuteAllLandAndEqualTheEditsOneByOne) {
  TempDir dir;
  const std::string store = FreshPostgresStore("writers");
  ASSERT_FALSE(store.empty());
  BuildTerrain(store);

  // Each writer: random polygons, one command each, until the time is up; the tag names the
  // polygon's file.
  struct Landed {
    std::string tag;
    std::string file;
  };
  std::vector<std::vector<Landed>> landed(kWriters);
  std::vector<std::vector<std::string>> failures(kWriters);
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(Seconds());
  std::vector<std::thread> writers;
  for (int w = 0; w < kWriters; ++w)
    writers.emplace_back([&, w] {
      std::mt19937_64 random(1000 + w);
      for (int k = 0; std::chrono::steady_clock::now() < until; ++k) {
        std::string tag = "w";
        tag += std::to_string(w) + "n" + std::to_string(k);
        const std::string file = dir.Path(tag + ".geojson");
        std::ofstream(file) << RandomPolygon(random);
        CliResult r = RunCli("polygon add " + Quote(store) + " " + Quote(file) +
                             " --surface terrain --mode fill --tag " + tag);
        if (r.exit_code == 0)
          landed[w].push_back({tag, file});
        else
          failures[w].push_back(tag + ": " + r.err);
      }
    });
  for (std::thread& t : writers) t.join();
  size_t total = 0;
  for (int w = 0; w < kWriters; ++w) {
    EXPECT_TRUE(failures[w].empty()) << failures[w].front();
    EXPECT_GE(landed[w].size(), size_t{2}) << "writer " << w;
    total += landed[w].size();
  }
  CliResult check = RunCli("check --full " + Quote(store));
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;

  // Every committed feature is there, once; their order by id.
  std::map<std::string, std::string> file_of;
  for (const auto& list : landed)
    for (const Landed& l : list) file_of[l.tag] = l.file;
  auto db = Connection::Open(store, Connection::Mode::kReadOnly);
  ASSERT_TRUE(db.ok()) << db.status().ToString();
  auto order =
      (*db)->Prepare("SELECT g.value FROM features f JOIN tags g ON g.id = f.tag ORDER BY f.id");
  ASSERT_TRUE(order.ok());
  std::vector<std::string> tags;
  while (*(*order)->Step()) tags.push_back((*order)->ColumnText(0));
  ASSERT_EQ(tags.size(), total);
  EXPECT_EQ(std::set<std::string>(tags.begin(), tags.end()).size(), total);
  for (const std::string& tag : tags) ASSERT_TRUE(file_of.count(tag)) << tag;

  // The same features one by one, in that order, on SQLite give the same surface.
  const std::string sqlite = dir.Path("one_by_one.tinbase");
  BuildTerrain(sqlite);
  for (const std::string& tag : tags) {
    CliResult r = RunCli("polygon add " + Quote(sqlite) + " " + Quote(file_of[tag]) +
                         " --surface terrain --mode fill --tag " + tag);
    ASSERT_EQ(r.exit_code, 0) << tag << ": " << r.err;
  }
  // Equal by the exact local test: the same vertices and constraints, and both surfaces pass the
  // full check (each is then the constrained Delaunay triangulation of those, up to co-circular
  // ties, which grid points have everywhere: docs/design.md, "Pitfalls"), so the same number of
  // triangles; and the same area under each paint.
  CliResult serial_check = RunCli("check --full " + Quote(sqlite));
  EXPECT_EQ(serial_check.exit_code, 0) << serial_check.out << serial_check.err;
  const Surface concurrent = Read(store), serial = Read(sqlite);
  ASSERT_GT(serial.triangles, 0);
  EXPECT_TRUE(concurrent.vertices == serial.vertices)
      << "the vertices differ:" << Difference(concurrent.vertices, serial.vertices);
  EXPECT_TRUE(concurrent.constraints == serial.constraints)
      << "the constraints differ:" << Difference(concurrent.constraints, serial.constraints);
  EXPECT_EQ(concurrent.triangles, serial.triangles);
  ASSERT_EQ(concurrent.area_by_paint.size(), serial.area_by_paint.size());
  for (const auto& [paint, area] : serial.area_by_paint) {
    ASSERT_TRUE(concurrent.area_by_paint.count(paint)) << paint;
    EXPECT_NEAR(concurrent.area_by_paint.at(paint), area, 1e-9 * area) << paint;
  }
}

}  // namespace
}  // namespace tinbase::testing
