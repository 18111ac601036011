// DEM mosaics: sheets of one grid imported together or one by one rebuild the original, later
// sheets win unless told otherwise, overviews follow, and an import is whole or absent (an error
// after any block write, or kill -9).

#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <set>
#include <thread>

#include "core/raster/gdal_raster.h"
#include "db/dem_store.h"
#include "db/migrations.h"
#include "db/sql/connection.h"
#include "db/store.h"
#include "tests/support/dem_checks.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::CompareSamples;
using testing::CountDifferences;
using testing::CutSheet;
using testing::DataPath;
using testing::ExpectedBlocks;
using testing::FloorDivForTest;
using testing::kVinschgauSheets;
using testing::MakeStore;
using testing::Mosaic;
using testing::OpenRaster;
using testing::Options;
using testing::SheetCut;
using testing::TableChecksums;
using testing::TempDir;
using testing::WholeBox;
using testing::WriteGrid;

TEST_F(Mosaic, FourSheetsInOneImportRebuildTheOriginal) {
  auto store = MakeStore(dir_, "");
  DemStore dems(*store);
  auto report = dems.Import({paths_["nw"], paths_["ne"], paths_["sw"], paths_["se"]},
                            Options("vinschgau", 64));
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  auto dem = dems.Find("vinschgau");
  ASSERT_TRUE(dem.ok());
  auto stored = dems.ReadGrid(*dem);
  ASSERT_TRUE(stored.ok()) << stored.status().ToString();
  EXPECT_EQ(CountDifferences(*stored, original_), 0);
  EXPECT_EQ(report->blocks_written, static_cast<int64_t>(ExpectedBlocks(original_, 64).size()));
}

// Importing the sheets one by one from the south-east grows the DEM west and north; blocks stay
// anchored at the first sheet's origin, so each import writes only the blocks its sheet touches.
TEST_F(Mosaic, SheetsAddedOneByOneGrowTheDemAndWriteOnlyTouchedBlocks) {
  auto store = MakeStore(dir_, "");
  DemStore dems(*store);
  constexpr int kBlock = 32;
  const SheetCut& first = kVinschgauSheets[3];  // se
  for (int i : {3, 1, 2, 0}) {
    const SheetCut& s = kVinschgauSheets[i];
    SCOPED_TRACE(s.name);
    auto report = dems.Import({paths_[s.name]}, Options("grown", kBlock));
    ASSERT_TRUE(report.ok()) << report.status().ToString();
    // Blocks are counted from the first sheet's corner in the original's columns and rows.
    std::set<std::pair<int64_t, int64_t>> touched;
    for (int r = s.row; r < s.row + s.height; ++r)
      for (int c = s.col; c < s.col + s.width; ++c)
        if (original_.IsValid(c, r))
          touched.emplace(FloorDivForTest(c - first.col, kBlock),
                          FloorDivForTest(r - first.row, kBlock));
    EXPECT_EQ(report->blocks_written, static_cast<int64_t>(touched.size()));
    EXPECT_EQ(report->dem.block_col0 + report->dem.geometry.origin_x / 250,
              first.col + original_.geometry.origin_x / 250);
  }
  auto dem = dems.Find("grown");
  ASSERT_TRUE(dem.ok());
  auto stored = dems.ReadGrid(*dem);
  ASSERT_TRUE(stored.ok()) << stored.status().ToString();
  EXPECT_EQ(CountDifferences(*stored, original_), 0);
  EXPECT_EQ(dem->block_col0, first.col);
  EXPECT_EQ(dem->block_row0, first.row);
  auto sources = store->db().Prepare("SELECT json_array_length(sources) FROM dems");
  ASSERT_TRUE(sources.ok() && *(*sources)->Step());
  EXPECT_EQ((*sources)->ColumnInt(0), 4);
  EXPECT_EQ(CompareSamples(dems, *dem, OpenRaster(DataPath("dem/elev_vinschgau.tif")).dataset(),
                           original_, 99, 200),
            200);
}

// Samples served from the cache before an import that rewrites the blocks are not served after
// it: in the importing DemStore at once, in another connection (as another process would be)
// after its next Find.
TEST_F(Mosaic, ImportInvalidatesCachedBlocks) {
  auto store = MakeStore(dir_, "");
  DemStore dems(*store);
  ASSERT_TRUE(dems.Import({paths_["ne"]}, Options("v", 32)).ok());
  auto other_store = Store::Open(store->path(), Store::Access::kReadOnly);
  ASSERT_TRUE(other_store.ok());
  DemStore other(**other_store);
  auto dem = dems.Find("v");
  ASSERT_TRUE(dem.ok());
  auto other_dem = other.Find("v");
  ASSERT_TRUE(other_dem.ok());
  // A point of the north-east sheet with data around it.
  const GridGeometry& g = dem->geometry;
  double x = 0, y = 0;
  double before = 0;
  bool found = false;
  for (int64_t r = 5; r < g.height - 5 && !found; ++r)
    for (int64_t c = 5; c < g.width - 5 && !found; ++c) {
      x = g.CellCenterX(c) + 0.25 * g.cell_x;
      y = g.CellCenterY(r);
      auto z = dems.Sample(*dem, x, y);
      found = z.ok();
      if (found) before = *z;
    }
  ASSERT_TRUE(found);
  ASSERT_EQ(*other.Sample(*other_dem, x, y), before);  // warm in both
  Grid raised = *OpenRaster(paths_["ne"]).Read();
  for (float& v : raised.cells) v += 1000;
  const std::string raised_path = dir_.Path("ne_raised.tif");
  WriteGrid(raised_path, raised, raised.crs_wkt);
  ASSERT_TRUE(dems.Import({raised_path}, Options("v", 32)).ok());
  auto after = dems.Sample(*dem, x, y);
  ASSERT_TRUE(after.ok());
  EXPECT_NEAR(*after, before + 1000, 1e-3);
  other_dem = other.Find("v");
  ASSERT_TRUE(other_dem.ok());
  auto other_after = other.Sample(*other_dem, x, y);
  ASSERT_TRUE(other_after.ok());
  EXPECT_EQ(*other_after, *after);
}

TEST_F(Mosaic, LaterSheetsWinUnlessKeepFirst) {
  // The north-east sheet raised by 1000 m: in the overlap its cells tell which sheet won.
  Grid raised = *OpenRaster(paths_["ne"]).Read();
  for (float& v : raised.cells) v += 1000;
  const std::string raised_path = dir_.Path("ne_raised.tif");
  WriteGrid(raised_path, raised, raised.crs_wkt);
  const SheetCut& nw = kVinschgauSheets[0];
  const SheetCut& ne = kVinschgauSheets[1];
  for (bool keep_first : {false, true}) {
    SCOPED_TRACE(keep_first ? "keep_first" : "later wins");
    TempDir dir;
    auto store = MakeStore(dir, "");
    DemStore dems(*store);
    DemImportOptions options = Options("m", 64);
    options.keep_first = keep_first;
    auto report = dems.Import({paths_["nw"], raised_path}, options);
    ASSERT_TRUE(report.ok()) << report.status().ToString();
    auto grid = dems.ReadGrid(report->dem);
    ASSERT_TRUE(grid.ok());
    int64_t checked = 0;
    for (int r = 0; r < nw.height; ++r)
      for (int c = 0; c < ne.col + ne.width; ++c) {
        if (!original_.IsValid(c, r)) continue;
        const bool in_nw = c < nw.col + nw.width;
        const bool in_ne = c >= ne.col;
        const float expected = original_.At(c, r) + ((in_ne && (!in_nw || !keep_first)) ? 1000 : 0);
        ASSERT_EQ(grid->At(c, r), expected) << c << ", " << r;
        ++checked;
      }
    EXPECT_GT(checked, 20000);
  }
}

TEST_F(Mosaic, SheetWarpedForAnExistingDemLandsOnItsGrid) {
  auto store = MakeStore(dir_, "EPSG:4326");
  DemStore dems(*store);
  auto first = dems.Import({paths_["nw"]}, Options("geo", 64));
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  auto second = dems.Import({paths_["se"]}, Options("geo", 64));
  ASSERT_TRUE(second.ok()) << second.status().ToString();
  EXPECT_TRUE(second->warped);
  const GridGeometry& a = first->dem.geometry;
  const GridGeometry& b = second->dem.geometry;
  EXPECT_EQ(a.cell_x, b.cell_x);
  EXPECT_GT(b.width, a.width);
  EXPECT_GT(b.height, a.height);
  EXPECT_NEAR(std::remainder((b.origin_x - a.origin_x) / a.cell_x, 1.0), 0, 1e-6);
  // The south-east corner of the Vinschgau lies in the second sheet only; it has data.
  const double lon = b.MaxX() - 20 * b.cell_x;
  const double lat = b.MinY() - 20 * b.cell_y;
  auto z = dems.Sample(second->dem, lon, lat);
  EXPECT_TRUE(z.ok()) << z.status().ToString();
}

// Sheets added one at a time keep the overviews equal to those computed over the whole mosaic
// at once, while each import recomputes only the overview blocks above what it wrote.
TEST_F(Mosaic, OverviewsStayUpToDateAsSheetsAreAdded) {
  auto store = MakeStore(dir_, "");
  DemStore dems(*store);
  // A first sheet of one 16 x 16 block has one level; the next ones add levels as well as blocks.
  const std::string tiny = dir_.Path("tiny.tif");
  CutSheet(DataPath("dem/elev_vinschgau.tif"), tiny, 130, 110, 16, 16);
  const std::vector<std::string> order = {tiny, paths_["se"], paths_["ne"], paths_["sw"],
                                          paths_["nw"]};
  int64_t total_overview_blocks = 0;
  int64_t last_overview_blocks = 0;
  for (const std::string& path : order) {
    auto report = dems.Import({path}, Options("step", 16));
    ASSERT_TRUE(report.ok()) << report.status().ToString();
    if (path == tiny) {
      EXPECT_EQ(report->dem.levels, 1);
    }
    last_overview_blocks = report->overview_blocks_written;
  }
  auto once = dems.Import(order, Options("once", 16));
  ASSERT_TRUE(once.ok()) << once.status().ToString();
  total_overview_blocks = once->overview_blocks_written;
  EXPECT_LT(last_overview_blocks, total_overview_blocks);
  auto step = dems.Find("step");
  ASSERT_TRUE(step.ok());
  ASSERT_EQ(step->levels, once->dem.levels);
  EXPECT_GE(step->levels, 4);
  for (int level = 0; level < step->levels; ++level) {
    SCOPED_TRACE("level " + std::to_string(level));
    auto a = dems.ReadWindow(*step, WholeBox(step->geometry), level);
    auto b = dems.ReadWindow(once->dem, WholeBox(once->dem.geometry), level);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(CountDifferences(*a, *b), 0);
  }
}

// ---- Atomicity of imports: an error after any block write, and kill -9 mid-import.

// Block writes (level 0 and overviews) that importing `files` into `name` makes on `store`.
int64_t CountBlockWrites(Store& store, const std::vector<std::string>& files,
                         const std::string& name) {
  int64_t writes = 0;
  DemImportOptions options = Options(name, 32);
  options.after_block_write = [&](int64_t n) {
    writes = n;
    return Status::Ok();
  };
  EXPECT_TRUE(DemStore(store).Import(files, options).ok());
  return writes;
}

// The failure hook fails the import after block write k, for k from the first write to the last
// (every few, to stay quick), both creating a DEM and extending one with overviews: the import
// returns the error, the tables are as before, the store checks clean and reads as before.
TEST_F(Mosaic, ErrorAfterAnyBlockWriteLeavesTheStoreAsItWas) {
  const std::vector<std::string> first = {paths_["nw"], paths_["ne"]};
  const std::vector<std::string> second = {paths_["sw"], paths_["se"]};
  for (const bool extend : {false, true}) {
    SCOPED_TRACE(extend ? "extending a DEM" : "creating a DEM");
    TempDir dir;
    auto counting = MakeStore(dir, "", "count.tinbase");
    if (extend) CountBlockWrites(*counting, first, "v");
    const int64_t total = CountBlockWrites(*counting, extend ? second : first, "v");
    ASSERT_GT(total, 10);

    auto store = MakeStore(dir, "");
    DemStore dems(*store);
    if (extend) {
      ASSERT_TRUE(dems.Import(first, Options("v", 32)).ok());
    }
    const auto before = TableChecksums(store->path());
    std::optional<Grid> grid_before;
    if (extend) grid_before = *dems.ReadGrid(*dems.Find("v"));
    std::vector<int64_t> failing_writes;
    for (int64_t k = 1; k < total; k += std::max<int64_t>(1, total / 12))
      failing_writes.push_back(k);
    failing_writes.push_back(total);
    for (const int64_t k : failing_writes) {
      SCOPED_TRACE("failing after block write " + std::to_string(k) + " of " +
                   std::to_string(total));
      DemImportOptions options = Options("v", 32);
      options.after_block_write = [k](int64_t n) {
        return n == k ? Status::IOError("injected failure") : Status::Ok();
      };
      auto report = dems.Import(extend ? second : first, options);
      ASSERT_FALSE(report.ok());
      EXPECT_NE(report.status().message().find("injected failure"), std::string::npos);
      EXPECT_EQ(TableChecksums(store->path()), before);
      testing::ExpectStoreIntact(*store, /*full=*/true);
      if (extend) {
        auto dem = dems.Find("v");
        ASSERT_TRUE(dem.ok());
        EXPECT_EQ(CountDifferences(*dems.ReadGrid(*dem), *grid_before), 0);
      } else {
        EXPECT_EQ(dems.Find("v").status().code(), StatusCode::kNotFound);
      }
      if (HasFailure()) return;
    }
  }
}

// A child process imports two versions of the same sheet over each other, endlessly, and is
// killed with SIGKILL at random moments: afterwards the store checks clean and the DEM is one
// version or the other in every cell, never a mix of a half-written import.
TEST_F(Mosaic, KillNineMidImportLeavesWholeImportsOnly) {
  Grid raised = original_;
  for (float& z : raised.cells) z += 100;
  const std::string raised_path = dir_.Path("raised.tif");
  WriteGrid(raised_path, raised, original_.crs_wkt);
  const std::string original_path = DataPath("dem/elev_vinschgau.tif");
  auto store = MakeStore(dir_, "");
  ASSERT_TRUE(DemStore(*store).Import({original_path}, Options("v", 32)).ok());
  const std::string path = store->path();
  store.reset();

  std::mt19937 rng(20261122);
  std::uniform_int_distribution<int> delay_ms(0, 40);
  std::set<std::string> seen;
  for (int round = 0; round < 12; ++round) {
    int done[2];  // the child writes a byte after each whole import
    ASSERT_EQ(pipe(done), 0);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      close(done[0]);
      auto s = Store::Open(path);
      if (!s.ok()) _exit(2);
      DemStore dems(**s);
      for (int i = 0;; ++i) {
        if (!dems.Import({i % 2 ? original_path : raised_path}, Options("v", 32)).ok()) _exit(3);
        if (write(done[1], "x", 1) != 1) _exit(4);
      }
    }
    close(done[1]);
    // Kill during the import after the first (raised) or second (original) one is whole, at a
    // random moment of it: timing alone would depend on how loaded the machine is.
    for (int whole = 0; whole < 1 + round % 2; ++whole) {
      char byte = 0;
      ASSERT_EQ(read(done[0], &byte, 1), 1) << "the importing child died";
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms(rng)));
    ASSERT_EQ(kill(child, SIGKILL), 0);
    close(done[0]);
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the importing child stopped by itself: " << status;

    auto reopened = Store::Open(path);
    ASSERT_TRUE(reopened.ok()) << reopened.status().ToString();
    testing::ExpectStoreIntact(**reopened, /*full=*/true);
    DemStore dems(**reopened);
    auto dem = dems.Find("v");
    ASSERT_TRUE(dem.ok());
    auto grid = dems.ReadGrid(*dem);
    ASSERT_TRUE(grid.ok()) << grid.status().ToString();
    const auto differing = [&](const Grid& expected) {
      int64_t n = 0;
      for (size_t i = 0; i < expected.cells.size(); ++i) {
        const float a = grid->cells[i], b = expected.cells[i];
        n += !(a == b || (std::isnan(a) && std::isnan(b)));
      }
      return n;
    };
    ASSERT_EQ(grid->cells.size(), original_.cells.size());
    const int64_t as_original = differing(original_);
    const int64_t as_raised = differing(raised);
    EXPECT_TRUE(as_original == 0 || as_raised == 0)
        << "round " << round << ": " << as_original << " cells differ from the original and "
        << as_raised << " from the raised sheet";
    seen.insert(as_original == 0 ? "original" : "raised");
    if (HasFailure()) break;
  }
  EXPECT_EQ(seen.size(), 2u) << "the kills should land after both kinds of import";
}

}  // namespace
}  // namespace tinbase
