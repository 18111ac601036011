// A damaged DEM block is an error, never nodata: with one level-0 block of a store's DEM
// overwritten (its bytes through SQL, or its codec number), `dem sample`, `tin build` (DEM in
// memory and streamed), `polygon add` (draping its ring) and `check --full` fail with Corruption
// naming that block, and change nothing. The library calls say Corruption by code; the CLI says
// it in its one line.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "db/dem_store.h"
#include "db/polygon_editor.h"
#include "db/surface_builder.h"
#include "tests/support/cli_support.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::CliResult;
using testing::DataPath;
using testing::ExpectRejected;
using testing::Quote;
using testing::RunCli;
using testing::RunWrite;
using testing::StoreTarget;
using testing::TempDir;

class DemCorruptionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    RunWrite(store_, "init " + Quote(store_));
    RunWrite(store_, "dem import " + Quote(store_) + " " +
                         Quote(DataPath("geology/hamersley/dtm_rp.tif")) + " --block-size 64");
    RunWrite(store_, "tin build " + Quote(store_) + " --surface terrain --tolerance 10");
    // The DEM's centre and the level-0 block that holds it (docs/format.md: block (bx, by)
    // covers columns block_col0 + bx * block_size onwards, likewise rows).
    auto store = Store::Open(store_, Store::Access::kReadOnly);
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    DemStore dems(**store);
    auto dem = dems.Find("dtm_rp");
    ASSERT_TRUE(dem.ok()) << dem.status().ToString();
    const GridGeometry& g = dem->geometry;
    const int64_t col = g.width / 2, row = g.height / 2;
    x_ = g.origin_x + (static_cast<double>(col) + 0.5) * g.cell_x;
    y_ = g.origin_y + (static_cast<double>(row) + 0.5) * g.cell_y;
    cell_ = std::fabs(g.cell_x);
    bx_ = (col - dem->block_col0) / dem->block_size;
    by_ = (row - dem->block_row0) / dem->block_size;
    block_ =
        "DEM 'dtm_rp', level 0 block (" + std::to_string(bx_) + ", " + std::to_string(by_) + ")";
  }

  // Runs `set` (an SQL SET clause) on the centre's level-0 block row.
  void DamageBlock(const std::string& set) {
    auto store = Store::Open(store_);
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    const std::string sql = "UPDATE dem_blocks SET " + set +
                            " WHERE level = 0 AND bx = " + std::to_string(bx_) +
                            " AND by = " + std::to_string(by_);
    ASSERT_TRUE((*store)->db().Exec(sql).ok()) << sql;
    auto changed = (*store)->db().QueryInt("SELECT changes()");
    ASSERT_TRUE(changed.ok());
    ASSERT_EQ(*changed, 1) << "no block row at (" << bx_ << ", " << by_ << ")";
  }

  // Keeps the first half of the blob and zeroes the rest: the frame or the checksum fails.
  void OverwriteBlockBytes() {
    DamageBlock(
        "data = substr(data, 1, length(data) / 2) || zeroblob(length(data) - length(data) / 2)");
  }

  // A small square around the centre, well inside the damaged block.
  std::string Square() {
    return testing::WritePolygons(dir_, "square.geojson", {{testing::Ngon(x_, y_, 3 * cell_, 4)}});
  }

  std::string Point() const {
    std::ostringstream out;
    out.precision(17);
    out << x_ << " " << y_;
    return out.str();
  }

  // Every command that reads the damaged block refuses, naming it, and changes nothing.
  void ExpectEveryReaderRefuses() {
    const std::string s = Quote(store_);
    ExpectRejected(store_, "dem sample " + s + " -- " + Point(), block_);
    const std::string points = dir_.Path("points.txt");
    std::ofstream(points) << Point() << "\n";
    ExpectRejected(store_, "dem sample " + s + " --points " + Quote(points), block_);
    ExpectRejected(store_, "tin build " + s + " --surface again --tolerance 10", block_);
    ExpectRejected(store_, "tin build " + s + " --surface again --method rtin --tolerance 10",
                   block_);
    ExpectRejected(
        store_,
        "polygon add " + s + " " + Quote(Square()) + " --surface terrain --mode fill --tag granite",
        block_);
    // Streamed block by block (no cache: the greedy builder reads through a DemCellSource).
    const auto before = testing::TableChecksums(store_);
    CliResult streamed =
        RunCli("tin build " + s + " --surface again --tolerance 10", "TINBASE_DEM_CACHE_MIB=0");
    EXPECT_NE(streamed.exit_code, 0);
    EXPECT_NE(streamed.err.find(block_), std::string::npos) << streamed.err;
    EXPECT_EQ(testing::TableChecksums(store_), before);
    // The checker cannot verify invariants 6 and 7 over a block it cannot read.
    CliResult check = RunCli("check --full " + s);
    EXPECT_NE(check.exit_code, 0);
    EXPECT_NE((check.out + check.err).find(block_), std::string::npos) << check.out << check.err;
  }

  // The library's answers, by code. A fresh process-wide cache is not at hand here, so this runs
  // before any in-process read of the damaged block could have cached a good copy.
  void ExpectCorruptionCodes() {
    auto store = Store::Open(store_);
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    DemStore dems(**store);
    auto dem = dems.Find("dtm_rp");
    ASSERT_TRUE(dem.ok());
    const auto expect_corruption = [&](const Status& s, const std::string& what) {
      EXPECT_EQ(s.code(), StatusCode::kCorruption) << what << ": " << s.ToString();
      EXPECT_NE(s.message().find(block_), std::string::npos) << what << ": " << s.ToString();
    };
    expect_corruption(dems.Sample(*dem, x_, y_).status(), "Sample");
    expect_corruption(dems.Elevation(*dem, x_, y_).status(), "Elevation");
    SurfaceBuildOptions build;
    build.surface = "again";
    build.method = TerrainMethod::kVip;
    expect_corruption(BuildSurfaceFromDem(**store, build).status(), "BuildSurfaceFromDem");
    PolygonAddOptions add;
    add.surface = "terrain";
    add.file = Square();
    add.mode = FeatureMode::kErase;
    expect_corruption(AddPolygons(**store, add).status(), "AddPolygons");
  }

  TempDir dir_;
  std::string store_;
  double x_ = 0, y_ = 0, cell_ = 0;
  int64_t bx_ = 0, by_ = 0;
  std::string block_;
};

TEST_F(DemCorruptionTest, OverwrittenBlockBytesAreCorruptionNamingTheBlock) {
  OverwriteBlockBytes();
  ExpectCorruptionCodes();
  ExpectEveryReaderRefuses();
}

TEST_F(DemCorruptionTest, AnUnknownCodecIsCorruptionNotABadArgument) {
  DamageBlock("codec = 99");
  ExpectCorruptionCodes();
  ExpectEveryReaderRefuses();
}

// The same reads of an undamaged store succeed: the failures above are the block's doing.
TEST_F(DemCorruptionTest, TheSameReadsSucceedOnAnIntactStore) {
  const std::string s = Quote(store_);
  EXPECT_EQ(RunCli("dem sample " + s + " -- " + Point()).exit_code, 0);
  RunWrite(store_, "polygon add " + s + " " + Quote(Square()) +
                       " --surface terrain --mode fill --tag granite");
  RunWrite(store_, "tin build " + s + " --surface again --tolerance 10");
}

}  // namespace
}  // namespace tinbase
