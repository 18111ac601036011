// What the history tests compare (tests/db/history/): the feature rows of a store (ids, names,
// modes, levels, tags, attributes, geometry), its vertices, constraints and paint counts, and the
// exact mesh: every triangle row (vertices, neighbours, visibility, tag, block), vertex row (z to
// the bit, kind) and constraint row (feature, kind) under its id. A revert from the mesh images
// gives all of it back; one that fell back to re-refining the region (a later edit replaced the
// rows) gives back the features and every invariant of `check --full`, but the vertices there may
// differ (the greedy refinement of a region is not that of the whole surface). Header-only.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <string>
#include <vector>

#include "db/store.h"

namespace tinbase::testing {

struct SurfaceSignature {
  std::vector<std::string> vertices, constraints, features, paint;
  // The exact mesh rows (ExactMeshOf): compared by ExpectSameMesh only.
  std::vector<std::string> triangle_rows, vertex_rows, constraint_rows;
  bool operator==(const SurfaceSignature&) const = default;
};

// The rows of `sql` read column by column through the seam, so the same on both backends:
// `types` gives each column's type, 'i' integer, 'd' double (its bits in hex), 't' text, 'b' blob
// (hex); NULL is "null".
inline std::vector<std::string> TypedRowsOf(Store& store, const std::string& sql,
                                            const std::string& types) {
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
    for (size_t c = 0; c < types.size(); ++c) {
      const int col = static_cast<int>(c);
      line += c ? "|" : "";
      char hex[20];
      if (stmt->ColumnIsNull(col)) {
        line += "null";
      } else if (types[c] == 'i') {
        line += std::to_string(stmt->ColumnInt(col));
      } else if (types[c] == 'd') {
        std::snprintf(
            hex, sizeof hex, "%016llx",
            static_cast<unsigned long long>(std::bit_cast<uint64_t>(stmt->ColumnDouble(col))));
        line += hex;
      } else if (types[c] == 't') {
        line += stmt->ColumnText(col);
      } else {
        size_t size = 0;
        const uint8_t* data = stmt->ColumnBlob(col, &size);
        for (size_t k = 0; k < size; ++k) {
          std::snprintf(hex, sizeof hex, "%02x", data[k]);
          line += hex;
        }
      }
    }
    out.push_back(line);
  }
  std::sort(out.begin(), out.end());  // NULLs sort differently by backend
  return out;
}

// Fills the exact mesh rows of `s` from `store`.
inline void ExactMeshOf(Store& store, SurfaceSignature* s) {
  s->triangle_rows = TypedRowsOf(store,
                                 "SELECT id, surface, v0, v1, v2, n0, n1, n2, visible, tag, block "
                                 "FROM triangles",
                                 "iiiiiiiiiii");
  s->vertex_rows = TypedRowsOf(store, "SELECT id, surface, x, y, z, kind FROM vertices", "iidddt");
  s->constraint_rows =
      TypedRowsOf(store, "SELECT surface, va, vb, feature, kind FROM constraints", "iiiit");
}

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
  ExactMeshOf(store, &s);
  return s;
}

// The first of `expected` and `actual` that differ, or "" when they are equal.
inline std::string FirstDifference(const std::vector<std::string>& expected,
                                   const std::vector<std::string>& actual) {
  for (size_t k = 0; k < std::max(expected.size(), actual.size()); ++k) {
    const std::string e = k < expected.size() ? expected[k] : "(none)";
    const std::string a = k < actual.size() ? actual[k] : "(none)";
    if (e != a) return "row " + std::to_string(k) + ": expected " + e + ", got " + a;
  }
  return "";
}

// The exact mesh and the features of `expected` and `actual` as one message: "" when equal.
inline std::string MeshDifference(const SurfaceSignature& expected,
                                  const SurfaceSignature& actual) {
  const std::pair<const char*, std::string> parts[] = {
      {"features", FirstDifference(expected.features, actual.features)},
      {"triangles", FirstDifference(expected.triangle_rows, actual.triangle_rows)},
      {"vertices", FirstDifference(expected.vertex_rows, actual.vertex_rows)},
      {"constraints", FirstDifference(expected.constraint_rows, actual.constraint_rows)}};
  for (const auto& [what, difference] : parts)
    if (!difference.empty()) return std::string(what) + ", " + difference;
  return "";
}

// Fails the test when the features or the exact mesh rows differ, naming the first difference.
inline void ExpectSameMesh(const SurfaceSignature& expected, const SurfaceSignature& actual,
                           const std::string& when) {
  EXPECT_EQ(MeshDifference(expected, actual), "") << when;
}

// Fails the test when the feature rows differ, naming the first difference.
inline void ExpectSameFeatures(const SurfaceSignature& expected, const SurfaceSignature& actual,
                               const std::string& when) {
  EXPECT_EQ(expected.features, actual.features) << when;
}

}  // namespace tinbase::testing
