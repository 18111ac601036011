// MemoryLocator: bulk location's walk over a MemoryMesh, giving for every point exactly the answer
// the stored path of LocatePoints gives (db/query/bulk_locate.h): the same triangle, z, paint and
// step count, including which triangle answers a point on an edge or a vertex.
//
// That answer depends on where each walk starts and on the edge order it tries, so this follows
// the stored path rule for rule: the last answer's triangle is tried first; otherwise the walk
// starts where the previous walk ended when the point is within two blocks of that walk's point,
// else it jumps to the lowest triangle id of the point's block (or of the nearest non-empty ring
// of blocks, up to three rings, else the surface's first triangle); the walk tries a triangle's
// edges from a random one, seeded by the point, skipping the edge it came through
// (db/point_locator.cc, whose constants and seed this repeats; the bulk location tests compare
// both paths answer by answer, steps included, so a change to one that is not made to the other
// fails them). Thread-safety: one per thread; the mesh is shared read-only.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "core/geometry/predicates.h"
#include "db/point_locator.h"
#include "db/query/memory_mesh.h"
#include "db/surface_store.h"

namespace tinbase {

class MemoryLocator {
 public:
  // REQUIRES: `mesh` is of `surface`; both outlive the locator.
  MemoryLocator(const MemoryMesh& mesh, const SurfaceInfo& surface)
      : mesh_(mesh), surface_(surface) {}

  // Where `p` lies, given the points located before it by this locator: a pointer to the answer,
  // valid until the next call; null when `p` is outside the surface. Corruption when the links
  // are inconsistent (two triangles that do not link back across their edge, a walk that does
  // not end), as the stored walk reports it. REQUIRES: finite coordinates.
  Result<const Location*> Locate(const Point2& p);

 private:
  bool LastHolds(const Point2& p) const;
  bool NearLastWalk(const Point2& p) const;
  std::optional<uint32_t> Jump(const Point2& p) const;
  // The triangle holding p by the walk from `start`; nullopt when p is outside; *steps counts the
  // triangles visited.
  Result<std::optional<uint32_t>> Walk(uint32_t start, const Point2& p, int* steps) const;
  void Answer(uint32_t t, const Point2& p, int steps);
  std::string Where() const { return "surface '" + surface_.name + "'"; }

  const MemoryMesh& mesh_;
  const SurfaceInfo& surface_;
  std::optional<uint32_t> last_;       // the last answer's triangle (answer_ holds its paint)
  std::optional<uint32_t> last_walk_;  // where the last walk ended
  Point2 last_walk_point_{};           // the point of that walk
  Location answer_;
};

}  // namespace tinbase
