// Line features for the tests of softlines and 3D lines: in-memory features for the polygon
// editor, and the constraint rows and vertices they leave in a store. Header-only.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "db/polygon_editor.h"
#include "db/store.h"

namespace tinbase::testing {

// One line feature `label` of `mode` (with its own z when `z` is given: z[i] for points[i]).
inline MemoryFeature LineFeature(const std::string& label, FeatureMode mode,
                                 const std::vector<Point2>& points,
                                 const std::optional<std::vector<double>>& z = std::nullopt) {
  MemoryFeature m;
  m.label = label;
  m.mode = mode;
  m.lines = {points};
  if (z) {
    m.z_from = ZFrom::kFeature;
    m.line_z = {*z};
  }
  return m;
}

// Adds `features` to surface "terrain" in one transaction.
inline Result<PolygonAddReport> AddLines(Store& store, std::vector<MemoryFeature> features) {
  PolygonAddOptions o;
  o.surface = "terrain";
  o.features = std::move(features);
  return AddPolygons(store, o);
}

// A constraint row with its kind and its vertices' coordinates.
struct ConstraintOf {
  int64_t va = 0, vb = 0;
  std::string kind;
  double ax = 0, ay = 0, az = 0, bx = 0, by = 0, bz = 0;
};

// The constraint rows of `feature`, in (va, vb) order.
inline std::vector<ConstraintOf> ConstraintsOf(Store& store, int64_t feature) {
  auto stmt = store.db().Prepare(
      "SELECT c.va, c.vb, c.kind, a.x, a.y, a.z, b.x, b.y, b.z FROM constraints c "
      "JOIN vertices a ON a.id = c.va JOIN vertices b ON b.id = c.vb WHERE c.feature = " +
      std::to_string(feature) + " ORDER BY c.va, c.vb");
  EXPECT_TRUE(stmt.ok()) << stmt.status().ToString();
  std::vector<ConstraintOf> out;
  while (stmt.ok() && *(*stmt)->Step()) {
    Statement& s = **stmt;
    out.push_back({s.ColumnInt(0), s.ColumnInt(1), s.ColumnText(2), s.ColumnDouble(3),
                   s.ColumnDouble(4), s.ColumnDouble(5), s.ColumnDouble(6), s.ColumnDouble(7),
                   s.ColumnDouble(8)});
  }
  return out;
}

}  // namespace tinbase::testing
