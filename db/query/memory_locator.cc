// MemoryLocator: see memory_locator.h.
#include "db/query/memory_locator.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cstdlib>
#include <random>

namespace tinbase {

namespace {

// As db/point_locator.cc: the rings of blocks a jump searches, and the blocks between two points
// within which the second walk starts where the first ended.
constexpr int kJumpRings = 3;
constexpr int64_t kNearBlocks = 2;

std::string PointText(const Point2& p) {
  char buf[64];
  char* end = buf;
  *end++ = '(';
  end = std::to_chars(end, buf + sizeof buf, p.x).ptr;
  *end++ = ',';
  *end++ = ' ';
  end = std::to_chars(end, buf + sizeof buf, p.y).ptr;
  *end++ = ')';
  return std::string(buf, end);
}

double ZAt(const MemoryMesh& mesh, uint32_t t, const Point2& p) {
  return PlaneZ(mesh.Triangle(t).p, mesh.Heights(t), p.x, p.y);
}

}  // namespace

Result<const Location*> MemoryLocator::Locate(const Point2& p) {
  if (LastHolds(p)) {
    answer_.z = ZAt(mesh_, *last_, p);
    answer_.steps = 0;
    return &answer_;
  }
  std::optional<uint32_t> start = last_walk_;
  if (!start || !NearLastWalk(p)) start = Jump(p);
  if (!start) return nullptr;  // a surface without triangles
  int steps = 0;
  TB_ASSIGN_OR_RETURN(const std::optional<uint32_t> found, Walk(*start, p, &steps));
  if (!found) return nullptr;
  last_walk_ = found;
  last_walk_point_ = p;
  Answer(*found, p, steps);
  return &answer_;
}

bool MemoryLocator::LastHolds(const Point2& p) const {
  if (!last_) return false;
  const std::array<Point2, 3>& c = mesh_.Triangle(*last_).p;
  for (int i = 0; i < 3; ++i)
    if (Orientation(c[(i + 1) % 3], c[(i + 2) % 3], p) < 0) return false;
  return true;
}

bool MemoryLocator::NearLastWalk(const Point2& p) const {
  const BlockGrid& g = surface_.blocks;
  return std::abs(g.ColumnOf(p.x) - g.ColumnOf(last_walk_point_.x)) <= kNearBlocks &&
         std::abs(g.RowOf(p.y) - g.RowOf(last_walk_point_.y)) <= kNearBlocks;
}

std::optional<uint32_t> MemoryLocator::Jump(const Point2& p) const {
  const BlockGrid& grid = surface_.blocks;
  const int64_t bx = grid.ColumnOf(p.x), by = grid.RowOf(p.y);
  for (int64_t r = 0; r <= kJumpRings; ++r) {
    for (int64_t dy = -r; dy <= r; ++dy) {
      for (int64_t dx = -r; dx <= r; ++dx) {
        if (std::max(std::abs(dx), std::abs(dy)) != r) continue;  // ring r only
        const int64_t cx = bx + dx, cy = by + dy;
        if (cx < 0 || cy < 0 || cx >= BlockGrid::kStride || cy >= BlockGrid::kStride) continue;
        if (std::optional<uint32_t> t = mesh_.FirstInBlock(BlockGrid::Pack(cx, cy))) return t;
      }
    }
  }
  return mesh_.AnyTriangle();
}

Result<std::optional<uint32_t>> MemoryLocator::Walk(uint32_t start, const Point2& p,
                                                    int* steps) const {
  // The stored walk's seed (db/point_locator.cc), so both try edges in the same order.
  std::minstd_rand rng(
      static_cast<uint32_t>(std::bit_cast<uint64_t>(p.x) * 31 ^ std::bit_cast<uint64_t>(p.y)) | 1u);
  uint32_t current = start;
  int32_t came_from = MemoryTriangle::kBoundary;  // none yet: no triangle has this position
  // On a valid triangulation the walk ends with probability 1; broken links can make it cycle.
  int64_t step_limit = int64_t{1} << 16;
  bool limit_checked = false;
  for (;;) {
    ++*steps;
    if (*steps > step_limit) {
      if (limit_checked)
        return Status::Corruption(Where() + ": the walk to " + PointText(p) +
                                  " does not end; run tinbase check");
      step_limit = std::max(step_limit, 4 * static_cast<int64_t>(mesh_.TriangleCount()) + 16);
      limit_checked = true;
    }
    const MemoryTriangle& tri = mesh_.Triangle(current);
    const std::array<Point2, 3>& c = tri.p;
    // The edge we came through has p on its inner side, so it needs no test.
    const int first = static_cast<int>(rng() % 3);
    int exit_edge = -1;
    for (int k = 0; k < 3 && exit_edge < 0; ++k) {
      const int i = (first + k) % 3;
      if (came_from >= 0 && tri.n[i] == came_from) continue;
      if (Orientation(c[(i + 1) % 3], c[(i + 2) % 3], p) < 0) exit_edge = i;
    }
    if (exit_edge < 0) {
      for (int i = 0; i < 3; ++i) {
        if (came_from >= 0 && tri.n[i] == came_from &&
            Orientation(c[(i + 1) % 3], c[(i + 2) % 3], p) < 0)
          return Status::Corruption(
              Where() + ": triangle " + std::to_string(mesh_.TriangleId(current)) +
              " and its neighbour " +
              std::to_string(mesh_.TriangleId(static_cast<uint32_t>(came_from))) +
              " do not share the edge they link across; run tinbase check");
      }
      return std::optional<uint32_t>(current);
    }
    const int32_t next = tri.n[exit_edge];
    // Strictly beyond a boundary edge is outside: domains are convex (db/point_locator.cc).
    if (next == MemoryTriangle::kBoundary) return std::optional<uint32_t>();
    came_from = static_cast<int32_t>(current);
    current = static_cast<uint32_t>(next);
  }
}

void MemoryLocator::Answer(uint32_t t, const Point2& p, int steps) {
  answer_.z = ZAt(mesh_, t, p);
  answer_.steps = steps;
  if (last_ == t) return;  // same triangle: same id and paint
  last_ = t;
  answer_.triangle = mesh_.TriangleId(t);
  answer_.visible = mesh_.Visible(t);
  answer_.tag = mesh_.Tag(t);
}

}  // namespace tinbase
