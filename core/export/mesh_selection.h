// MeshSelection: the triangles of a Tin an export writes, and the vertices they use, renumbered
// densely in first-use order when triangles are left out, so an exported file never carries
// orphan vertices. Every writer in core/export takes one. Thread-safety: pure function.
#pragma once

#include <cstdint>
#include <vector>

#include "core/tin/tin.h"

namespace tinbase {

struct MeshSelection {
  std::vector<uint32_t> triangles;    // indices into tin.triangles, in tin order
  std::vector<uint32_t> vertices;     // indices into tin.vertices, in output order
  std::vector<int64_t> output_index;  // tin vertex -> output position, -1 when not written
};

// Every triangle and vertex of `tin` in its own order, or with `visible_only` the visible
// triangles and the vertices they use. REQUIRES: every triangle's vertices are in range.
MeshSelection SelectTriangles(const Tin& tin, bool visible_only);

}  // namespace tinbase
