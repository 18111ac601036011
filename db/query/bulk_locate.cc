// Bulk point location: see bulk_locate.h.
#include "db/query/bulk_locate.h"

#include <array>
#include <optional>

#include "db/mesh/mesh_tables.h"
#include "db/query/memory_locator.h"
#include "db/query/memory_mesh.h"

namespace tinbase {

namespace {

// The triangle of the last answer, in memory: sorted input puts several points in a row into one
// triangle, and those are answered here without reading the store.
class LastTriangle {
 public:
  LastTriangle(Store& store, const SurfaceInfo& surface) : surfaces_(store), surface_(surface) {}

  // The answer for (x, y) when the last triangle holds it (on its edges too).
  std::optional<Location> Holds(const Point2& q) const {
    if (!location_) return std::nullopt;
    for (int i = 0; i < 3; ++i)
      if (Orientation(p_[(i + 1) % 3], p_[(i + 2) % 3], q) < 0) return std::nullopt;
    Location answer = *location_;
    answer.z = PlaneZ(p_, z_, q.x, q.y);
    answer.steps = 0;
    return answer;
  }

  // Remembers `where`, reading its corners when it is another triangle than the last.
  Status Remember(const Location& where) {
    if (location_ && location_->triangle == where.triangle) return Status::Ok();
    TB_ASSIGN_OR_RETURN(const TriangleRow row, surfaces_.Triangle(surface_, where.triangle));
    for (int i = 0; i < 3; ++i) {
      TB_ASSIGN_OR_RETURN(const VertexRow v, surfaces_.Vertex(surface_, row.v[i]));
      p_[i] = {v.x, v.y};
      z_[i] = v.z;
    }
    location_ = where;
    return Status::Ok();
  }

 private:
  SurfaceStore surfaces_;
  const SurfaceInfo& surface_;
  std::optional<Location> location_;
  std::array<Point2, 3> p_{};
  std::array<double, 3> z_{};
};

Status LocateStored(Store& store, const SurfaceInfo& surface, const std::vector<Point2>& points,
                    const LocatedPointSink& sink) {
  PointLocator locator(store, surface);
  LastTriangle last(store, surface);
  for (size_t i = 0; i < points.size(); ++i) {
    if (std::optional<Location> held = last.Holds(points[i])) {
      TB_RETURN_IF_ERROR(sink(i, points[i], &*held));
      continue;
    }
    Result<Location> where = locator.Locate(points[i].x, points[i].y);
    if (where.ok()) {
      TB_RETURN_IF_ERROR(last.Remember(*where));
      TB_RETURN_IF_ERROR(sink(i, points[i], &*where));
    } else if (where.status().code() == StatusCode::kNotFound) {
      TB_RETURN_IF_ERROR(sink(i, points[i], nullptr));
    } else {
      return where.status();
    }
  }
  return Status::Ok();
}

Status LocateInMemory(const MemoryMesh& mesh, const SurfaceInfo& surface,
                      const std::vector<Point2>& points, const LocatedPointSink& sink) {
  MemoryLocator locator(mesh, surface);
  for (size_t i = 0; i < points.size(); ++i) {
    TB_ASSIGN_OR_RETURN(const Location* where, locator.Locate(points[i]));
    TB_RETURN_IF_ERROR(sink(i, points[i], where));
  }
  return Status::Ok();
}

}  // namespace

Result<LocatePath> ChooseLocatePath(Store& store, const SurfaceInfo& surface, size_t points) {
  const int64_t most = kLoadTrianglesPerPoint * static_cast<int64_t>(points);
  TB_ASSIGN_OR_RETURN(const int64_t triangles,
                      MeshTables(store.db(), surface).CountTrianglesUpTo(most + 1));
  return triangles <= most ? LocatePath::kInMemory : LocatePath::kStored;
}

Status LocatePointsBy(LocatePath path, Store& store, const SurfaceInfo& surface,
                      const std::vector<Point2>& points, const LocatedPointSink& sink) {
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  if (path == LocatePath::kChoose) {
    TB_ASSIGN_OR_RETURN(path, ChooseLocatePath(store, surface, points.size()));
  }
  if (path == LocatePath::kInMemory) {
    TB_ASSIGN_OR_RETURN(const std::optional<MemoryMesh> mesh, MemoryMesh::Load(store, surface));
    if (mesh) return LocateInMemory(*mesh, surface, points, sink);
  }
  return LocateStored(store, surface, points, sink);
}

Status LocatePoints(Store& store, const SurfaceInfo& surface, const std::vector<Point2>& points,
                    const LocatedPointSink& sink) {
  return LocatePointsBy(LocatePath::kChoose, store, surface, points, sink);
}

}  // namespace tinbase
