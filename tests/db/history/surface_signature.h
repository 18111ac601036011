// What "the same surface" means for the history tests (issue 28: equal up to co-circular ties,
// judged by the exact local test): the same vertices (x, y, z), the same constrained edges with
// their owners, the same feature rows, and the same count of triangles, of visible ones and of
// each tag. With the full check passing (every unconstrained edge locally Delaunay by the exact
// in-circle test, every constraint an edge), two surfaces with equal signatures are the same
// constrained Delaunay triangulation but for the diagonal of co-circular quads, and those carry
// the same paint (a quad holds no constraint, so both its halves lie in the same features).
// Header-only.
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
    for (int c = 0; c < stmt->ColumnCount(); ++c)
      line += (c ? "|" : "") + (stmt->ColumnIsNull(c) ? std::string("null") : stmt->ColumnText(c));
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

// Fails the test with what differs first.
inline void ExpectSameSurface(const SurfaceSignature& expected, const SurfaceSignature& actual,
                              const std::string& when) {
  const auto first_difference = [](const std::vector<std::string>& a,
                                   const std::vector<std::string>& b) {
    for (size_t k = 0; k < std::min(a.size(), b.size()); ++k)
      if (a[k] != b[k]) return "row " + std::to_string(k) + ": " + a[k] + " vs " + b[k];
    return "counts " + std::to_string(a.size()) + " vs " + std::to_string(b.size());
  };
  EXPECT_TRUE(expected.vertices == actual.vertices)
      << when << ": vertices differ, " << first_difference(expected.vertices, actual.vertices);
  EXPECT_TRUE(expected.constraints == actual.constraints)
      << when << ": constraints differ, "
      << first_difference(expected.constraints, actual.constraints);
  EXPECT_TRUE(expected.features == actual.features)
      << when << ": features differ, " << first_difference(expected.features, actual.features);
  EXPECT_TRUE(expected.paint == actual.paint)
      << when << ": paint differs, " << first_difference(expected.paint, actual.paint);
}

}  // namespace tinbase::testing
