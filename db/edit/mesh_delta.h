// MeshDelta: everything one edit changes in a surface's mesh rows, as a value (LevelDB's
// VersionEdit). The edit's stages build it (db/edit/mesh_delta_builder.h) after every read;
// one writer applies it to the store (db/edit/mesh_delta_writer.h), the only place the edit writes
// mesh rows, and the mesh cache applies the same value to the rows it holds (MeshCache::Apply).
// Ids are final: the builder numbers new rows on from the tables' largest ids.
// Plain data; not synchronised.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/tin/tin.h"
#include "db/mesh/mesh_edge.h"
#include "db/mesh/mesh_rows.h"
#include "db/mesh_cache.h"

namespace tinbase {

// Triangle `triangle` takes this paint (a no-op for a row that already has it).
struct TriangleRepaint {
  int64_t triangle = 0;
  bool visible = true;
  std::optional<int64_t> tag;  // tags.id
};

// In the order the writer applies it; each group is one write step (the fault hook's numbering,
// db/edit/update_engine_test_hooks.h).
struct MeshDelta {
  int64_t surface = 0;
  std::string surface_name;  // for messages
  // The conflict region is every triangle of the surface: its rows go by one statement, and the
  // bulk inserts run with foreign keys unchecked (every key they bind holds by construction).
  bool whole_surface = false;

  // Step 1: new vertices (ring points, crossings, refinement points), ids first_vertex, ... in
  // order. Step 2: z of the region's existing vertices that a replace feature sets or restores.
  int64_t first_vertex = 0;
  std::vector<TinVertex> new_vertices;
  std::vector<VertexZ> region_z;

  // Step 3: new triangles, ids first_triangle, ... in order (block order).
  int64_t first_triangle = 0;
  std::vector<TriangleRow> new_triangles;

  // Step 4: the conflict region's rows (in the order found; with whole_surface every triangle of
  // the surface below first_triangle) and the vertices left on no constraint (ascending).
  std::vector<int64_t> deleted_triangles;
  std::vector<int64_t> deleted_vertices;

  // Step 5: stored triangles across the region's outline, with their links to the new ones
  // (ascending id; the whole row, of which only the links differ).
  std::vector<std::pair<int64_t, TriangleRow>> relinked;

  // Step 6: the constraint rows of removed features go; kept constraints the patch split lose
  // their rows (their pieces are among added_constraints); the new rows (edge, feature; 0 for a
  // row without feature), sorted and unique.
  std::vector<int64_t> removed_features;
  std::vector<MeshEdge> split_constraints;
  std::vector<std::pair<MeshEdge, int64_t>> added_constraints;
  // Not written: edges of the new triangles that carry no constraint, for a mesh cache that does
  // not know every constraint (empty otherwise).
  std::vector<MeshEdge> free_edges;

  // Step 7: paint of stored triangles around the changed features (ascending id, changed ones
  // only) and of the triangles of uniform blocks (ascending id; rows that have it stay), then z
  // of the vertices around that a replace feature sets or restores.
  std::vector<TriangleRepaint> repaints;
  std::vector<TriangleRepaint> block_repaints;
  std::vector<VertexZ> around_z;
};

}  // namespace tinbase
