// Fault injection under SQLite (docs/reliability.md): each writing operation of the store runs
// with the fault VFS (tests/support/fault_vfs.h) failing its Nth I/O, for N = 1, 2, ... (every
// k-th N for an operation of many I/Os, see kRunsPerLoop) until a run reaches its end without
// meeting the fault. Every run must end in success or in a clean
// error (one line, a storage code), and the store, reopened without faults, must pass the full
// check and hold all or none of the operation: its tables equal those before the run or those of
// a run with no fault (each of which passes the full check), and SQLite's integrity_check finds
// its file sound. This reaches what the engine's step hooks do not: the open, the WAL, the
// statement journals, the commit and the checkpoint.
#include "tests/support/fault_vfs.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "db/dem_store.h"
#include "db/point_import.h"
#include "db/polygon_editor.h"
#include "db/store.h"
#include "db/surface_builder.h"
#include "db/surface_store.h"
#include "db/tiles/tile_pyramid.h"
#include "tests/support/polygon_files.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::FaultError;
using testing::FaultPlan;
using testing::ScopedFaultVfs;
using testing::TempDir;

// Centre of the Hamersley DEM (EPSG:28350), and its cell size.
constexpr double kCx = 539300, kCy = 7497340, kCell = 344.404386931320971;
// A run that meets no fault ends the loop; this bounds it should the count never settle.
constexpr int64_t kMaxRuns = 4000;
// An operation of more I/Os than this is failed at every k-th of them only (k the smallest that
// keeps a loop to about this many runs; each of the four loops starts at its own offset, so
// together they reach more of them). TINBASE_FAULT_EVERY_IO=1 fails every one.
constexpr int64_t kRunsPerLoop = 150;

using Operation = std::function<Status(Store&, const TempDir&)>;

// The rows of `sql`, as text, for comparing.
std::string RowsOf(Connection& db, const std::string& sql, int columns) {
  auto rows = db.Prepare(sql);
  if (!rows.ok()) return rows.status().ToString();
  std::string text;
  while (true) {
    auto row = (*rows)->Step();
    if (!row.ok()) return row.status().ToString();
    if (!*row) break;
    for (int c = 0; c < columns; ++c) text += (*rows)->ColumnText(c) + ",";
    text += ";";
  }
  return text;
}

// The tables' checksums, with what differs between two runs of one command left out: the
// changes log's wall-clock column and the random token of the DEM block cache in meta.
std::map<std::string, std::string> TablesOf(const std::string& path) {
  auto sums = testing::TableChecksums(path);
  sums.erase("changes");
  sums.erase("meta");
  auto db = Connection::Open(path, Connection::Mode::kReadOnly);
  if (!db.ok()) return {{"<error>", db.status().ToString()}};
  sums["changes (but time)"] = RowsOf(**db,
                                      "SELECT tx, coalesce(surface, -1), coalesce(feature, -1), "
                                      "action, removed, added FROM changes ORDER BY tx",
                                      6);
  sums["meta (but the cache token)"] =
      RowsOf(**db, "SELECT key, value FROM meta WHERE key <> 'dem_cache_token' ORDER BY key", 2);
  return sums;
}

void CopyStore(const std::string& from, const std::string& to) {
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(to + suffix);
  std::filesystem::copy_file(from, to);
}

Status RunOn(const std::string& path, const Operation& op, const TempDir& dir) {
  auto store = Store::Open(path);
  if (!store.ok()) return store.status();
  return op(**store, dir);
}

// SQLite's own verdict on the file's pages and indexes.
std::string SqliteVerdict(Store& store) {
  auto stmt = store.db().Prepare("PRAGMA integrity_check(1)");
  if (!stmt.ok()) return stmt.status().ToString();
  auto row = (*stmt)->Step();
  if (!row.ok()) return row.status().ToString();
  return *row ? (*stmt)->ColumnText(0) : "no answer";
}

// The full check (every invariant of docs/design.md) on the store at `path`.
void ExpectIntact(const std::string& path) {
  auto store = Store::Open(path);
  ASSERT_TRUE(store.ok()) << store.status().ToString();
  testing::ExpectStoreIntact(**store, /*full=*/true);
}

// The tables whose rows differ between `a` and `b`, for messages.
std::string Differing(const std::map<std::string, std::string>& a,
                      const std::map<std::string, std::string>& b) {
  std::string names;
  for (const auto& [table, sum] : a) {
    auto it = b.find(table);
    if (it == b.end() || it->second != sum) names += (names.empty() ? "" : ", ") + table;
  }
  for (const auto& [table, sum] : b)
    if (!a.count(table)) names += (names.empty() ? "" : ", ") + table;
  return names.empty() ? "none" : names;
}

struct LoopReport {
  int64_t runs = 0;       // runs that met their fault
  int64_t failed = 0;     // of those, ending in an error
  int64_t completed = 0;  // of those, ending with the operation's transaction in the store
};

class FaultVfsTest : public ::testing::Test {
 protected:
  // Stores made once: "empty" (no DEM, the CRS set), "dem" (the Hamersley DEM), "surface"
  // (with a greedy surface "terrain" at 10 m over it), "feature" (with a fill polygon on it) and
  // "coarse" (the DEM with a greedy surface "coarse" at 100 m, for the tile pyramid: the loop
  // builds the pyramid once per I/O of it, so the surface is kept small).
  static void SetUpTestSuite() {
    bases_ = new TempDir();
    auto store = Store::Create(Base("empty"), "EPSG:28350");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store->reset();
    std::filesystem::copy_file(Base("empty"), Base("dem"));
    store = Store::Open(Base("dem"));
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    ASSERT_TRUE(ImportDem(**store, *bases_).ok());
    store->reset();
    std::filesystem::copy_file(Base("dem"), Base("surface"));
    store = Store::Open(Base("surface"));
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    ASSERT_TRUE(BuildTerrain(**store, *bases_).ok());
    store->reset();
    std::filesystem::copy_file(Base("surface"), Base("feature"));
    store = Store::Open(Base("feature"));
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    ASSERT_TRUE(AddPolygon(**store, *bases_, false).ok());
    store->reset();
    std::filesystem::copy_file(Base("dem"), Base("coarse"));
    store = Store::Open(Base("coarse"));
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    ASSERT_TRUE(BuildSurface(**store, "coarse", 100).ok());
  }
  static void TearDownTestSuite() {
    delete bases_;
    bases_ = nullptr;
  }
  static std::string Base(const std::string& name) { return bases_->Path(name + ".tinbase"); }

  static Status ImportDem(Store& store, const TempDir&) {
    return DemStore(store).Import({testing::DataPath("geology/hamersley/dtm_rp.tif")}, {}).status();
  }
  static Status BuildTerrain(Store& store, const TempDir&) {
    return BuildSurface(store, "terrain", 10);
  }
  // A coarse surface: the loop runs the build once per I/O of it.
  static Status BuildCoarse(Store& store, const TempDir&) {
    return BuildSurface(store, "coarse", 40);
  }
  static Status BuildSurface(Store& store, const std::string& name, double tolerance) {
    SurfaceBuildOptions o;
    o.surface = name;
    o.greedy.tolerance = tolerance;
    return BuildSurfaceFromDem(store, o).status();
  }
  // The tile pyramid of "coarse", six levels deep (a few hundred I/Os): the loop runs the build
  // once per I/O of it.
  static Status BuildTiles(Store& store, const TempDir&) {
    auto surface = SurfaceStore(store).Find("coarse");
    if (!surface.ok()) return surface.status();
    TileBuildOptions o;
    o.max_zoom = 5;
    o.extensions.normals = true;
    return BuildTilePyramid(store, *surface, o).status();
  }
  // Replaces the feature of "feature" by a polygon that overlaps it, as the file comment of
  // UpdatePolygon says: one transaction that removes the old feature and adds the new one.
  static Status UpdateLastPolygon(Store& store, const TempDir& dir) {
    auto id = store.db().QueryInt("SELECT max(id) FROM features");
    if (!id.ok()) return id.status();
    PolygonAddOptions o;
    o.file = testing::WritePolygons(dir, "moved.geojson",
                                    {{testing::Ngon(kCx + 2 * kCell, kCy + kCell, 5 * kCell, 10)}});
    return UpdatePolygon(store, *id, o).status();
  }
  // Adds fill polygons to "terrain" from a file of two: the first when `rings` has bit 1, the
  // second when it has bit 2 (an attribute filter picks them, so each keeps its attributes), one
  // transaction per feature with `each`.
  static Status AddPolygon(Store& store, const TempDir& dir, bool each, unsigned rings = 1) {
    PolygonAddOptions o;
    o.surface = "terrain";
    o.mode = FeatureMode::kFill;
    o.tag = "fill";
    o.each = each;
    o.file = testing::WritePolygons(dir, "rings.geojson",
                                    {{testing::Ngon(kCx, kCy, 4 * kCell, 12)},
                                     {testing::Ngon(kCx + 10 * kCell, kCy, 3 * kCell, 9)}});
    if (rings == 1) o.where = "unit = 'u0'";
    if (rings == 2) o.where = "unit = 'u1'";
    auto report = AddPolygons(store, o);
    if (!report.ok()) return report.status();
    // With `each` a failed feature is reported, not returned: the test wants the failure.
    if (!report->failures.empty()) return Status::IOError(report->failures.front());
    return Status::Ok();
  }
  static Status ImportXyz(Store& store, const TempDir& dir) {
    const std::string path = dir.Path("points.xyz");
    std::ofstream out(path);
    out.precision(17);
    for (int i = 0; i < 40; ++i)
      for (int j = 0; j < 40; ++j)
        out << kCx + i * 97.3 + (j % 3) << " " << kCy + j * 101.9 + (i % 5) << " "
            << 500 + ((i * 7 + j * 13) % 29) << "\n";
    out.close();
    PointImportOptions o;
    o.file = path;
    o.surface = "points";
    return ImportPoints(store, o).status();
  }

  // Runs `op` on a copy of base store `base` failing I/O number N of `plan` for every N until a
  // run meets no fault; checks each run as the file comment says.
  // `partial` are operations whose outcome a failed run may also leave (with `each`, some of the
  // features committed).
  LoopReport Loop(const std::string& base, const Operation& op, FaultPlan plan, int offset,
                  const std::vector<Operation>& partial = {}) {
    const std::string work = dir_.Path("work.tinbase");
    std::vector<std::map<std::string, std::string>> partial_states;
    for (const Operation& p : partial) {
      CopyStore(Base(base), work);
      Status s = RunOn(work, p, dir_);
      EXPECT_TRUE(s.ok()) << "a part without faults: " << s.ToString();
      ExpectIntact(work);
      partial_states.push_back(TablesOf(work));
    }
    CopyStore(Base(base), work);
    ExpectIntact(work);
    const auto before = TablesOf(work);
    plan.path_prefix = work;
    plan.fail_at = 0;
    Status clean;
    int64_t operations = 0;
    {
      ScopedFaultVfs counter(plan);
      clean = RunOn(work, op, dir_);
      operations = counter.operations();
    }
    std::cout << "I/O operations without faults: " << operations << "\n";
    EXPECT_TRUE(clean.ok()) << "without faults: " << clean.ToString();
    ExpectIntact(work);
    const auto after = TablesOf(work);
    EXPECT_NE(before, after) << "the operation changed nothing";

    const bool every_io = std::getenv("TINBASE_FAULT_EVERY_IO") != nullptr;
    const int64_t stride =
        every_io ? 1 : std::max<int64_t>(1, (operations + kRunsPerLoop - 1) / kRunsPerLoop);
    LoopReport report;
    for (int64_t n = 1 + offset % stride; n <= kMaxRuns * stride; n += stride) {
      CopyStore(Base(base), work);
      plan.path_prefix = work;
      plan.fail_at = n;
      Status s;
      bool fired = false;
      {
        ScopedFaultVfs vfs(plan);
        s = RunOn(work, op, dir_);
        fired = vfs.fired();
      }
      const std::string where = std::string(testing::FaultErrorName(plan.error)) +
                                (plan.persistent ? " from" : " at") + " I/O " + std::to_string(n);
      if (!fired) {
        EXPECT_TRUE(s.ok()) << where << " never came, yet: " << s.ToString();
        break;
      }
      ++report.runs;
      if (!s.ok()) {
        ++report.failed;
        EXPECT_NE(s.code(), StatusCode::kInvalidArgument) << where << ": " << s.ToString();
        EXPECT_EQ(s.message().find('\n'), std::string::npos) << where << ": " << s.ToString();
      }
      const auto state = TablesOf(work);
      const bool done = state == after;
      report.completed += done;
      const bool part = !s.ok() && std::find(partial_states.begin(), partial_states.end(), state) !=
                                       partial_states.end();
      EXPECT_TRUE(done || part || state == before)
          << where << ": the store holds part of the operation (" << s.ToString() << ")";
      EXPECT_TRUE(!s.ok() || done) << where << ": success, but the store lacks the operation ("
                                   << Differing(state, after) << " differ from a run without "
                                   << "faults; " << Differing(state, before) << " from before)";
      // Equal tables to a state whose store passed the full check pass it too; what is left to
      // see is that the file opens for writing (WAL recovery included) and that SQLite finds its
      // pages sound.
      auto reopened = Store::Open(work);
      EXPECT_TRUE(reopened.ok()) << where << ": " << reopened.status().ToString();
      if (reopened.ok()) {
        EXPECT_EQ(SqliteVerdict(**reopened), "ok") << where;
      }
      if (::testing::Test::HasFailure()) {
        ADD_FAILURE() << "stopped at " << where;
        break;
      }
    }
    EXPECT_GT(report.runs, 0);
    std::cout << "every " << stride << " I/O from " << 1 + offset % stride
              << "; faults met: " << report.runs << ", errors: " << report.failed
              << ", completed anyway: " << report.completed << "\n";
    return report;
  }

  // Loops `op` under each error a disk gives: a transient EIO, a transient full disk, a short
  // write, and a disk that stays full from the Nth write on.
  void LoopEveryError(const std::string& base, const Operation& op,
                      const std::vector<Operation>& partial = {}) {
    int offset = 0;
    for (FaultError error : {FaultError::kIoError, FaultError::kFull, FaultError::kShortWrite}) {
      SCOPED_TRACE(testing::FaultErrorName(error));
      FaultPlan plan;
      plan.error = error;
      plan.kinds = error == FaultError::kIoError ? testing::kFaultAll : testing::kFaultWrite;
      Loop(base, op, plan, offset++, partial);
      if (HasFailure()) return;
    }
    SCOPED_TRACE("disk full from the Nth write on");
    FaultPlan full;
    full.error = FaultError::kFull;
    full.kinds = testing::kFaultWrite | testing::kFaultOpen;
    full.persistent = true;
    Loop(base, op, full, offset, partial);
  }

  static TempDir* bases_;
  TempDir dir_;
};

TempDir* FaultVfsTest::bases_ = nullptr;

TEST_F(FaultVfsTest, PolygonAdd) {
  // One polygon of the file's two.
  LoopEveryError("surface", [](Store& s, const TempDir& d) { return AddPolygon(s, d, false); });
}

TEST_F(FaultVfsTest, PolygonAddEach) {
  LoopEveryError("surface", [](Store& s, const TempDir& d) { return AddPolygon(s, d, true, 3); },
                 {[](Store& s, const TempDir& d) { return AddPolygon(s, d, true, 1); },
                  [](Store& s, const TempDir& d) { return AddPolygon(s, d, true, 2); }});
}

TEST_F(FaultVfsTest, PolygonRemove) {
  LoopEveryError("feature", [](Store& s, const TempDir&) {
    auto id = s.db().QueryInt("SELECT max(id) FROM features");
    if (!id.ok()) return id.status();
    return RemovePolygon(s, *id).status();
  });
}

TEST_F(FaultVfsTest, PolygonUpdate) { LoopEveryError("feature", UpdateLastPolygon); }

TEST_F(FaultVfsTest, TilesBuild) { LoopEveryError("coarse", BuildTiles); }

TEST_F(FaultVfsTest, TinBuild) { LoopEveryError("dem", BuildCoarse); }

TEST_F(FaultVfsTest, DemImport) { LoopEveryError("empty", ImportDem); }

TEST_F(FaultVfsTest, PointsImport) { LoopEveryError("empty", ImportXyz); }

}  // namespace
}  // namespace tinbase
