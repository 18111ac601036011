// Mesh rows: the one in-memory form of a row of the `triangles`, `vertices` and `constraints`
// tables (docs/format.md), shared by every reader and writer of a surface's mesh (MeshTables,
// MeshCache, PointLocator, SurfaceStore, the integrity checker and the update engine).
//
// A row's id is its key, not part of the row: rows live in maps and vectors keyed or ordered by
// id, and a row copied to a new id stays the same row. Plain values; thread-safety as any value.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "core/tin/tin.h"

namespace tinbase {

// One row of `triangles`: vertices counter-clockwise, n[i] the triangle across the edge opposite
// v[i] (nullopt on the domain boundary), the paint (visible, tag) and the centroid's block
// (CentroidBlock in db/surface_store.h, docs/design.md, "Point location").
struct TriangleRow {
  std::array<int64_t, 3> v{};
  std::array<std::optional<int64_t>, 3> n;
  bool visible = true;
  std::optional<int64_t> tag;  // tags.id
  int64_t block = 0;           // of its centroid (core/tin/block_grid.h)

  friend bool operator==(const TriangleRow&, const TriangleRow&) = default;
};

// One row of `vertices`: its columns are exactly a TinVertex's (x, y, z, kind), so the core's
// type is the row type and a Tin's vertices go to the table without a copy into another form.
using VertexRow = TinVertex;

// Vertex `id` as it becomes when an edit changes its z (x, y and kind stay).
struct VertexZ {
  int64_t id = 0;
  VertexRow vertex;
};

// One row of `constraints`: the edge (va, vb) with va < vb (the table's CHECK) and the feature
// whose ring or line it belongs to; nullopt for a constraint of the surface itself (a builder's
// breakline, written without feature).
struct ConstraintRow {
  int64_t va = 0;
  int64_t vb = 0;
  std::optional<int64_t> feature;

  friend bool operator==(const ConstraintRow&, const ConstraintRow&) = default;
};

}  // namespace tinbase
