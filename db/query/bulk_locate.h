// Bulk point location: the triangle, z and paint under each of many points of one surface,
// handed over one at a time in input order so a caller can stream them out.
//
// A point in the triangle of the previous answer is answered from memory (steps 0): sorted input
// puts several points in a row into one triangle. Otherwise each walk starts from the previous
// answer: points sorted along a path or in space cost a few steps each, and only a point far from
// the one before jumps first (db/point_locator.h). All answers come from one read snapshot.
//
// Two paths give the same answers, steps included (the tests compare them point by point):
// - stored: one PointLocator reads the rows each walk touches by key, a B-tree descent each;
// - in memory: the surface's rows are read once, in one scan of each table, into a MemoryMesh
//   (db/query/memory_mesh.h), and MemoryLocator walks there without reading the store again.
// A request takes the in-memory path when it is large against the surface (LocatePoints below).
// A point on an edge or a vertex is answered by whichever triangle around it the walk reaches
// first; both paths walk alike, so they pick the same one.
// Thread-safety: one call per Store at a time.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/predicates.h"
#include "db/point_locator.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

// Receives point `index` of the input and where it lies: null for a point outside the surface.
// A non-ok Status stops the run and is returned by LocatePoints.
using LocatedPointSink =
    std::function<Status(size_t index, const Point2& point, const Location* where)>;

// Locates each of `points` on `surface`, in order, calling `sink` once per point. A point
// outside the surface is an answer (null), not an error. Errors: the sink's, and PointLocator's
// other than NotFound (Corruption when the rows a walk reads are inconsistent).
//
// The in-memory path is taken when the surface has at most kLoadTrianglesPerPoint triangles per
// point of the request. Why that bound: loading reads every row of the surface once in a
// sequential scan, about 1.5 rows a triangle (a triangulation has about half as many vertices as
// triangles), so at most 3 rows a point; the stored path reads, for each point the last triangle
// does not hold, 3 to 4 rows by key (the start's existence, the walk's triangles, the answer's
// paint), each a descent of the B-tree, which costs several times a scanned row. Sorted input,
// where the last triangle holds about 40 % of the points, still reads about 2 rows a point by
// key, so the load is paid back at the bound, and scattered input (a jump and a walk of
// several triangles a point) far sooner. Deciding reads at most that many index entries
// (MeshTables::CountTrianglesUpTo), so a small request on a large surface is not slowed by the
// test. The loaded mesh takes about 100 bytes a triangle (170 while loading), so the bound keeps
// its memory within a small multiple of the request's own (its points and answers): a request
// size limit (the service's body limit) bounds it too.
// REQUIRES: finite coordinates.
Status LocatePoints(Store& store, const SurfaceInfo& surface, const std::vector<Point2>& points,
                    const LocatedPointSink& sink);

inline constexpr int64_t kLoadTrianglesPerPoint = 2;

// Which path LocatePointsBy takes: the choice above, or one of the two (the tests compare them).
enum class LocatePath { kChoose, kStored, kInMemory };

// The path LocatePoints takes for a request of `points` points: kInMemory or kStored.
Result<LocatePath> ChooseLocatePath(Store& store, const SurfaceInfo& surface, size_t points);

// LocatePoints on the path `path`. kInMemory still takes the stored path for a surface whose
// rows cannot be held by position (MemoryMesh::Load: a link naming a missing row).
Status LocatePointsBy(LocatePath path, Store& store, const SurfaceInfo& surface,
                      const std::vector<Point2>& points, const LocatedPointSink& sink);

}  // namespace tinbase
