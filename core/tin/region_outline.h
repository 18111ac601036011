// The outline of a region of a triangulation, and which triangles of a re-triangulation lie
// inside it, from the outline's topology alone. The update engine re-triangulates its conflict
// region R with R's outline constrained (db/edit/local_patch.cc) and keeps the triangles this
// classifies as inside. Plain data; not synchronised.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/tin/tin.h"

namespace tinbase {

// A region's outline in local vertex indices, directed as the region's triangles have it
// (counter-clockwise around the region): each vertex's outgoing edges (one or two, seldom more)
// in one array, so a lookup reads a few entries instead of hashing (ClassifyInside asks six
// times a triangle).
class DirectedOutline {
 public:
  // REQUIRES: every index in `edges` is below `vertices`.
  DirectedOutline(size_t vertices, const std::vector<std::pair<uint32_t, uint32_t>>& edges);
  // Whether (a, b) is an outline edge in that direction.
  bool Has(uint32_t a, uint32_t b) const;

 private:
  std::vector<uint32_t> first_;  // per vertex, where its edges start in to_
  std::vector<uint32_t> to_;
};

// Per triangle of `tin`: 1 when it lies in the region `outline` bounds, else 0. A triangle with an
// outline edge in the outline's direction is inside, with it reversed outside, and the rest take
// the class of their neighbours across edges that are not on the outline (0 when none is
// reached). Purely topological, so a sliver outside the region along a nearly straight outline
// is never taken for part of it.
std::vector<uint8_t> ClassifyInside(const Tin& tin, const DirectedOutline& outline);

}  // namespace tinbase
