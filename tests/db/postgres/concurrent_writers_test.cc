// Four writer processes edit one PostgreSQL store at once, each in its own quarter of the map,
// committing feature by feature (`polygon add --each`), so their transactions may interleave. Today
// a store has one writer at a time (docs/scaling.md): the test checks what that promises. Every
// writer succeeds, every feature is present, `check --full` passes, and the surface equals the one
// an SQLite store gets when the same features are added one by one in the order they committed.
#include <gtest/gtest.h>

#include <fstream>
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
constexpr int kPolygonsEach = 3;

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Writer w's polygons: squares of 2 km in its own quarter of the Hamersley DEM (EPSG:28350),
// tagged "w<w>p<k>".
std::string WriterPolygons(int w) {
  const double cx = 539298 + (w % 2 == 0 ? -17000 : 13000);
  const double cy = 7497339 + (w / 2 == 0 ? -17000 : 13000);
  std::ostringstream out;
  out.precision(17);
  out << R"({"type":"FeatureCollection","crs":{"type":"name","properties":{"name":"EPSG:28350"}},)"
      << R"("features":[)";
  for (int k = 0; k < kPolygonsEach; ++k) {
    const double x = cx + k * 4000, y = cy;
    out << (k == 0 ? "" : ",") << R"({"type":"Feature","properties":{"tag":"w)" << w << "p" << k
        << R"("},"geometry":{"type":"Polygon","coordinates":[[[)" << x << "," << y << "],["
        << x + 2000 << "," << y << "],[" << x + 2000 << "," << y + 2000 << "],[" << x << ","
        << y + 2000 << "],[" << x << "," << y << "]]]}}";
  }
  out << "]}";
  return out.str();
}

void BuildTerrain(const std::string& store) {
  RunWrite(store, "init " + Quote(store));
  RunWrite(store,
           "dem import " + Quote(store) + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")));
  RunWrite(store, "tin build " + Quote(store) + " --surface terrain --tolerance 10");
}

TEST(ConcurrentWritersTest, FourWritersAllLandAndEqualTheEditsOneByOne) {
  TempDir dir;
  const std::string store = FreshPostgresStore("writers");
  ASSERT_FALSE(store.empty());
  BuildTerrain(store);
  std::vector<std::string> files;
  for (int w = 0; w < kWriters; ++w) {
    std::string name = "w";  // (appended, not "w" + ...: GCC 12 warns a false -Wrestrict)
    name += std::to_string(w);
    files.push_back(dir.Path(name + ".geojson"));
    std::ofstream(files.back()) << WriterPolygons(w);
  }

  std::vector<CliResult> results(kWriters);
  std::vector<std::thread> writers;
  for (int w = 0; w < kWriters; ++w)
    writers.emplace_back([&, w] {
      results[w] = RunCli("polygon add " + Quote(store) + " " + Quote(files[w]) +
                          " --surface terrain --mode fill --tag-field tag --each");
    });
  for (std::thread& t : writers) t.join();
  for (int w = 0; w < kWriters; ++w) EXPECT_EQ(results[w].exit_code, 0) << results[w].err;
  CliResult check = RunCli("check --full " + Quote(store));
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;

  // Every feature is there, one transaction each; their commit order is the order of tx.
  auto db = Connection::Open(store, Connection::Mode::kReadOnly);
  ASSERT_TRUE(db.ok()) << db.status().ToString();
  auto order = (*db)->Prepare(
      "SELECT g.value FROM features f JOIN tags g ON g.id = f.tag ORDER BY f.tx, f.id");
  ASSERT_TRUE(order.ok());
  std::vector<std::string> tags;
  while (*(*order)->Step()) tags.push_back((*order)->ColumnText(0));
  ASSERT_EQ(tags.size(), size_t{kWriters * kPolygonsEach});
  EXPECT_EQ(*(*db)->QueryInt("SELECT count(DISTINCT tx) FROM features"), kWriters * kPolygonsEach);

  // The same features one by one, in that order, on SQLite give the same surface.
  const std::string sqlite = dir.Path("one_by_one.tinbase");
  BuildTerrain(sqlite);
  for (const std::string& tag : tags) {
    const int w = tag[1] - '0';
    RunWrite(sqlite, "polygon add " + Quote(sqlite) + " " + Quote(files[w]) +
                         " --surface terrain --mode fill --tag-field tag --where \"tag = '" + tag +
                         "'\"");
  }
  for (const auto& [target, name] : {std::pair{sqlite, "s.obj"}, std::pair{store, "p.obj"}})
    ASSERT_EQ(RunCli("export " + Quote(target) + " --surface terrain -o " + Quote(dir.Path(name)))
                  .exit_code,
              0);
  EXPECT_EQ(ReadAll(dir.Path("p.obj")), ReadAll(dir.Path("s.obj")));
}

}  // namespace
}  // namespace tinbase::testing
