// What the history tests compare (tests/db/history/): the feature rows of a store (ids, names,
// modes, levels, tags, attributes, geometry) and, for diagnostics, its vertices, constraints and
// paint counts. A revert re-triangulates the region of the features it takes out or puts back and
// refines it to the tolerance again, so the vertices there may differ from those the surface had
// (the greedy refinement of a region is not that of the whole surface); the features, and every
// invariant of `check --full`, are what a revert restores exactly. Header-only.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "db/store.h"

namespace tinbase::testing {

struct SurfaceSignature {
  std::vector<std::string> vertices, constraints, features, paint;
  bool operator==(const SurfaceSignature&) const = default;
};

// The rows of `sql` (every column as text, with "|" between), in the order the query gives.
inline std::vector<std::string> RowsOf(Store& store, const std::string& sql) {
  std::vector<std::string> out;
  auto prepared = store.db().Prepare(sql);
  EXPECT_TRUE(prepared.ok()) << sql;
  if (!prepared.ok()) return out;
  Statement* stmt = prepared->get();
  while (true) {
    auto row = stmt->Step();
    EXPECT_TRUE(row.ok()) << sql;
    if (!row.ok() || !*row) break;
    std::string line;
    for (int c = 0; c < stmt->ColumnCount(); ++c) {
      line += c ? "|" : "";
      line += stmt->ColumnIsNull(c) ? std::string("null") : stmt->ColumnText(c);
    }
    out.push_back(line);
  }
  return out;
}

inline SurfaceSignature SignatureOf(Store& store) {
  SurfaceSignature s;
  // printf('%!.17g') keeps every bit of a double.
  s.vertices = RowsOf(store,
                      "SELECT printf('%!.17g %!.17g %!.17g', x, y, z) AS p FROM vertices "
                      "ORDER BY p");
  s.constraints = RowsOf(store,
                         "SELECT printf('%!.17g %!.17g %!.17g %!.17g', a.x, a.y, b.x, b.y) AS e, "
                         "c.feature FROM constraints c JOIN vertices a ON a.id = c.va "
                         "JOIN vertices b ON b.id = c.vb ORDER BY e, c.feature");
  s.features = RowsOf(store,
                      "SELECT id, surface, name, mode, level, tag, attributes, hex(geometry) "
                      "FROM features ORDER BY id");
  s.paint = RowsOf(store,
                   "SELECT visible, coalesce(tag, -1), count(*) FROM triangles "
                   "GROUP BY visible, tag ORDER BY visible, tag");
  return s;
}

// Fails the test when the feature rows differ, naming the first difference.
inline void ExpectSameFeatures(const SurfaceSignature& expected, const SurfaceSignature& actual,
                               const std::string& when) {
  EXPECT_EQ(expected.features, actual.features) << when;
}

}  // namespace tinbase::testing
