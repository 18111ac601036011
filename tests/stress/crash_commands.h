// The writing commands of the crash loop (tests/stress/crash_loop_test.cc) and what "all or none"
// means for each: the rows a command's transactions write, counted before and after a round, must
// have moved by whole transactions. A command killed before its commit leaves every count as it
// was; one that ended before its kill did all of its work.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>

#include "db/sql/connection.h"

namespace tinbase::testing {

enum class Command {
  kAdd,
  kAddEach,
  kRemove,
  kUpdate,
  kPointsAdd,
  kPointsRemove,
  kRevert,
  kBuild,
  kPoints,
  kLas,
  kDem,
  kTilesBuild,
  kTilesUpdate,
  kCount
};

inline const char* Name(Command c) {
  static const char* names[] = {"polygon add",    "polygon add --each", "polygon remove",
                                "polygon update", "points add",         "points remove",
                                "revert",         "tin build",          "points import (XYZ)",
                                "las import",     "dem import",         "tiles build",
                                "tiles update"};
  return names[static_cast<int>(c)];
}

// The rows the commands write, counted, and what a round needs to pick its arguments.
struct Counts {
  int64_t changes = 0, features = 0, surfaces = 0, dems = 0, max_feature = 0;
  int64_t max_polygon = 0;    // the newest feature that is not survey points (0: none)
  int64_t max_points = 0;     // the newest `points` feature (0: none)
  int64_t last_edit_tx = 0;   // the newest polygon edit or revert (0: none)
  int64_t latest_change = 0;  // max(changes.tx)
  // The tile pyramid of "terrain": whether there is one, its transaction, its tiles' count and
  // the least and greatest transaction they were written in.
  int64_t pyramids = 0, pyramid_tx = -1, tiles = 0, tile_tx_min = -1, tile_tx_max = -1;
};

inline Counts CountRows(Connection& db) {
  Counts c;
  auto count = [&db](const char* sql) {
    auto n = db.QueryInt(sql);
    EXPECT_TRUE(n.ok()) << sql << ": " << n.status().ToString();
    return n.ok() ? *n : -2;
  };
  c.changes = count("SELECT count(*) FROM changes");
  c.features = count("SELECT count(*) FROM features");
  c.surfaces = count("SELECT count(*) FROM surfaces");
  c.dems = count("SELECT count(*) FROM dems");
  c.max_feature = count("SELECT coalesce(max(id), 0) FROM features");
  c.max_polygon = count("SELECT coalesce(max(id), 0) FROM features WHERE mode <> 'points'");
  c.max_points = count("SELECT coalesce(max(id), 0) FROM features WHERE mode = 'points'");
  c.last_edit_tx = count(
      "SELECT coalesce(max(tx), 0) FROM changes WHERE action LIKE 'polygon %' OR action LIKE "
      "'revert %'");
  c.latest_change = count("SELECT coalesce(max(tx), 0) FROM changes");
  const char* terrain = "(SELECT id FROM surfaces WHERE name = 'terrain')";
  c.pyramids = count("SELECT count(*) FROM tile_pyramids");
  c.pyramid_tx = count(
      (std::string("SELECT coalesce(max(tx), -1) FROM tile_pyramids WHERE surface = ") + terrain)
          .c_str());
  const std::string tiles = std::string(" FROM tiles WHERE surface = ") + terrain;
  c.tiles = count(("SELECT count(*)" + tiles).c_str());
  c.tile_tx_min = count(("SELECT coalesce(min(tx), -1)" + tiles).c_str());
  c.tile_tx_max = count(("SELECT coalesce(max(tx), -1)" + tiles).c_str());
  return c;
}

inline bool SameTiles(const Counts& a, const Counts& b) {
  return a.pyramids == b.pyramids && a.pyramid_tx == b.pyramid_tx && a.tiles == b.tiles &&
         a.tile_tx_min == b.tile_tx_min && a.tile_tx_max == b.tile_tx_max;
}

// All or none of each transaction of `command`, from the counts before (`b`) and after (`a`).
inline void ExpectWhole(Command command, const Counts& b, const Counts& a, bool finished) {
  const int64_t logged = a.changes - b.changes;
  const int64_t features = a.features - b.features;
  const int64_t surfaces = a.surfaces - b.surfaces;
  const int64_t dems = a.dems - b.dems;
  EXPECT_GE(logged, 0);
  // An edit of one transaction: at most one change row, all of it when it finished.
  const auto one_edit = [&] {
    EXPECT_LE(logged, 1);
    if (finished) {
      EXPECT_EQ(logged, 1);
    }
  };
  // A new surface or DEM: none or one, and one when the command finished.
  const auto one_new = [&](int64_t moved) {
    EXPECT_GE(moved, 0);
    EXPECT_LE(moved, 1);
    if (finished) {
      EXPECT_EQ(moved, 1);
    }
  };
  switch (command) {
    case Command::kAdd:
    case Command::kPointsAdd:
      one_edit();
      EXPECT_EQ(features, logged);
      break;
    case Command::kAddEach:
      EXPECT_LE(logged, 3);
      EXPECT_EQ(features, logged);
      break;
    case Command::kRemove:
    case Command::kPointsRemove:
      one_edit();
      EXPECT_EQ(features, -logged);
      break;
    case Command::kUpdate:
      one_edit();
      EXPECT_EQ(features, 0);
      EXPECT_EQ(a.max_feature > b.max_feature, logged == 1);
      break;
    case Command::kRevert:
      one_edit();
      break;
    case Command::kBuild:
      one_new(surfaces);
      EXPECT_EQ(logged, surfaces);
      break;
    case Command::kPoints:
    case Command::kLas:
      one_new(surfaces);
      break;
    case Command::kDem:
      one_new(dems);
      EXPECT_EQ(logged, 0);
      break;
    case Command::kTilesBuild:
      EXPECT_EQ(logged, 0);
      // Every tile of a new pyramid, written in one transaction stamped with the latest change.
      if (finished || !SameTiles(a, b)) {
        EXPECT_EQ(a.pyramids, std::max<int64_t>(b.pyramids, 1));
        EXPECT_EQ(a.pyramid_tx, a.latest_change);
        EXPECT_GT(a.tiles, 0);
        EXPECT_EQ(a.tile_tx_min, a.pyramid_tx);
        EXPECT_EQ(a.tile_tx_max, a.pyramid_tx);
      }
      break;
    case Command::kTilesUpdate:
      EXPECT_EQ(logged, 0);
      // The pyramid brought up to date in the one transaction that rewrote its tiles.
      if (finished || !SameTiles(a, b)) {
        EXPECT_EQ(a.pyramids, b.pyramids);
        EXPECT_EQ(a.pyramid_tx, a.latest_change);
        EXPECT_LE(a.tile_tx_max, a.pyramid_tx);
      }
      break;
    case Command::kCount:
      break;
  }
  const bool edits_features = command == Command::kAdd || command == Command::kAddEach ||
                              command == Command::kRemove || command == Command::kUpdate ||
                              command == Command::kPointsAdd || command == Command::kPointsRemove ||
                              command == Command::kRevert;
  EXPECT_TRUE(edits_features || features == 0) << "features moved by " << features;
  EXPECT_TRUE(logged > 0 || features == 0) << "features moved by " << features << " unlogged";
  const bool writes_tiles = command == Command::kTilesBuild || command == Command::kTilesUpdate;
  EXPECT_TRUE(writes_tiles || SameTiles(a, b)) << "the tiles moved";
  EXPECT_TRUE(command == Command::kDem || dems == 0) << "DEMs moved by " << dems;
}

}  // namespace tinbase::testing
