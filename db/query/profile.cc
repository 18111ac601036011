#include "db/query/profile.h"

#include <cmath>
#include <unordered_map>

#include "db/mesh/mesh_tables.h"
#include "db/point_locator.h"

namespace tinbase {

namespace {

// Reads the triangles the walk asks for, remembering their rows (for the paint) and vertices
// (consecutive triangles share two).
class ProfileReader {
 public:
  ProfileReader(Store& store, const SurfaceInfo& surface) : tables_(store.db(), surface) {}

  Result<WalkTriangle> Read(int64_t id) {
    Result<TriangleRow> row = tables_.Triangle(id);
    if (row.status().code() == StatusCode::kNotFound)
      return Status::Corruption(row.status().message() +
                                ", yet the walk was linked to it; run "
                                "tinbase check");
    TB_RETURN_IF_ERROR(row.status());
    WalkTriangle t;
    for (int i = 0; i < 3; ++i) {
      TB_ASSIGN_OR_RETURN(const VertexRow& v, Vertex(row->v[i]));
      t.v[i] = row->v[i];
      t.p[i] = {v.x, v.y};
      t.z[i] = v.z;
      t.n[i] = row->n[i];
    }
    rows_[id] = *row;
    return t;
  }

  // Reads the tag dictionary (small) once, for Paint.
  Status ReadTags() {
    TB_ASSIGN_OR_RETURN(tags_, tables_.TagValues());
    return Status::Ok();
  }

  // The paint of a triangle Read returned. An unknown tag reads as none (CheckStore reports
  // it: unknown-tag).
  ProfileStretch Paint(int64_t triangle) const {
    const TriangleRow& row = rows_.at(triangle);
    ProfileStretch s;
    s.triangle = triangle;
    s.visible = row.visible;
    if (row.tag) {
      if (auto it = tags_.find(*row.tag); it != tags_.end()) s.tag = it->second;
    }
    return s;
  }

 private:
  Result<VertexRow> Vertex(int64_t id) {
    if (auto it = vertices_.find(id); it != vertices_.end()) return it->second;
    Result<VertexRow> v = tables_.Vertex(id);
    if (v.status().code() == StatusCode::kNotFound)
      return Status::Corruption(v.status().message() +
                                ", yet a triangle has it; run tinbase "
                                "check");
    TB_RETURN_IF_ERROR(v.status());
    vertices_.emplace(id, *v);
    return *v;
  }

  MeshTables tables_;
  std::unordered_map<int64_t, TriangleRow> rows_;
  std::unordered_map<int64_t, VertexRow> vertices_;
  std::unordered_map<int64_t, std::string> tags_;
};

Status CheckLine(const std::vector<Point2>& line) {
  if (line.size() < 2)
    return Status::InvalidArgument("a profile line needs at least two points, got " +
                                   std::to_string(line.size()));
  for (size_t k = 0; k < line.size(); ++k)
    if (!std::isfinite(line[k].x) || !std::isfinite(line[k].y))
      return Status::InvalidArgument("profile point " + std::to_string(k + 1) + " is not finite");
  for (const Point2& p : line)
    if (p.x != line.front().x || p.y != line.front().y) return Status::Ok();
  return Status::InvalidArgument(
      "a profile line needs two distinct points; all its points are "
      "the same");
}

}  // namespace

Result<SurfaceProfile> ProfileAlong(Store& store, const SurfaceInfo& surface,
                                    const std::vector<Point2>& line) {
  TB_RETURN_IF_ERROR(CheckLine(line));
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  PointLocator locator(store, surface);
  Result<Location> start = locator.LocateTriangle(line.front().x, line.front().y);
  if (start.status().code() == StatusCode::kNotFound)
    return Status::NotFound("profile point 1: " + start.status().message());
  TB_RETURN_IF_ERROR(start.status());
  ProfileReader reader(store, surface);
  TB_ASSIGN_OR_RETURN(LineWalk walk,
                      WalkLine(line, start->triangle, [&](int64_t id) { return reader.Read(id); }));
  SurfaceProfile profile;
  profile.stations = std::move(walk.stations);
  TB_RETURN_IF_ERROR(reader.ReadTags());
  for (int64_t triangle : walk.triangles) profile.stretches.push_back(reader.Paint(triangle));
  return profile;
}

}  // namespace tinbase
