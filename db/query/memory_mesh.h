// MemoryMesh: one surface's triangles and vertices held in compact arrays for point location, read
// in one scan of each table (MeshTables' id-order reads) instead of one keyed lookup per row a
// walk touches. Rows are renumbered by position: links and corners are array indices, so a walk
// is index arithmetic with no lookup at all.
//
// It is a copy of one read snapshot: the caller holds the snapshot while it loads and uses it,
// and makes a new one after any write. Besides the rows it keeps what the stored walk's jump
// reads by key (db/point_locator.cc): the lowest triangle id of each centroid block, which is the
// row "any triangle of block b" returns (the (surface, block) index lists a block's rows in id
// order), and the row "any triangle of the surface" returns. Thread-safety: immutable once
// loaded; any number of readers.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/predicates.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

// A triangle by position: its corners' plan coordinates counter-clockwise as stored, n[i] the
// position of the triangle across the edge opposite corner i (kBoundary on the domain's edge),
// and its paint. Coordinates are copied in rather than referred to by vertex, so a walk's step
// reads one cache line instead of four scattered ones.
struct alignas(64) MemoryTriangle {
  static constexpr int32_t kBoundary = -1;
  static constexpr uint32_t kHidden = uint32_t{1} << 31;
  std::array<Point2, 3> p{};
  std::array<int32_t, 3> n{};
  uint32_t paint = 0;  // kHidden when invisible, | 1 + the tag's position (0: no tag)
};

class MemoryMesh {
 public:
  // Reads every triangle and vertex row of `surface`, and the tag dictionary. Returns nullopt
  // when the rows cannot be held by position: a link or corner naming a row that is not in the
  // surface (the stored walk reports that as Corruption, and only when it reaches the row, so
  // the caller keeps the stored walk for such a store), or more triangles or tags than a
  // position holds. Errors of the store as MeshTables returns them.
  // REQUIRES: a ReadSnapshot or WriteTransaction held around the call and every use.
  static Result<std::optional<MemoryMesh>> Load(Store& store, const SurfaceInfo& surface);

  size_t TriangleCount() const { return triangles_.size(); }
  const MemoryTriangle& Triangle(uint32_t t) const { return triangles_[t]; }
  // The corners' heights, in corner order.
  const std::array<double, 3>& Heights(uint32_t t) const { return heights_[t]; }
  int64_t TriangleId(uint32_t t) const { return triangle_ids_[t]; }
  bool Visible(uint32_t t) const { return (triangles_[t].paint & MemoryTriangle::kHidden) == 0; }
  // The tag's value; nullopt without tag or when the tag is not a row of `tags` (as the stored
  // walk reports it).
  const std::optional<std::string>& Tag(uint32_t t) const;

  // The triangle with the lowest id among those whose centroid block is `packed_block`; nullopt
  // when the block holds none.
  std::optional<uint32_t> FirstInBlock(int64_t packed_block) const;
  // The triangle "any triangle of the surface" returns; nullopt for a surface without triangles.
  std::optional<uint32_t> AnyTriangle() const { return any_; }

 private:
  // Moves first_in_block_ into block_grid_ when the blocks' bounding rectangle is small: a jump
  // then costs an array read instead of a hash lookup.
  void GridBlocks();

  std::vector<MemoryTriangle> triangles_;
  std::vector<std::array<double, 3>> heights_;
  std::vector<int64_t> triangle_ids_;  // ascending
  std::vector<std::optional<std::string>> tag_values_;
  std::unordered_map<int64_t, uint32_t> first_in_block_;
  // Dense form of first_in_block_ over columns [col0_, col0_ + cols_) and rows [row0_, ...): the
  // position, -1 for an empty block.
  std::vector<int32_t> block_grid_;
  int64_t col0_ = 0, row0_ = 0, cols_ = 0, rows_ = 0;
  std::optional<uint32_t> any_;
};

}  // namespace tinbase
