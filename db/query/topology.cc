#include "db/query/topology.h"

#include <algorithm>

#include "db/mesh/mesh_tables.h"
#include "db/point_locator.h"

namespace tinbase {

namespace {

// A vertex has few triangles around it; a rotation longer than this follows broken links.
constexpr int kMaxStar = 1 << 16;

int CornerOf(const TriangleRow& t, int64_t vertex) {
  for (int i = 0; i < 3; ++i)
    if (t.v[i] == vertex) return i;
  return -1;
}

// Turns around `vertex` from triangle `start` (which has it) through n[(k + step) % 3], step 1
// counter-clockwise, 2 clockwise, appending the triangles met after `start` and their rows.
// Returns true when the turn came back to `start` (the vertex is inside the surface).
Result<bool> Turn(MeshTables& tables, const SurfaceInfo& surface, int64_t vertex, int64_t start,
                  const TriangleRow& start_row, int step, std::vector<int64_t>* ids,
                  std::vector<TriangleRow>* rows) {
  TriangleRow row = start_row;
  for (int count = 0; count < kMaxStar; ++count) {
    const std::optional<int64_t> next = row.n[(CornerOf(row, vertex) + step) % 3];
    if (!next) return false;
    if (*next == start) return true;
    Result<TriangleRow> read = tables.Triangle(*next);
    if (read.status().code() == StatusCode::kNotFound)
      return Status::Corruption("surface '" + surface.name + "': the triangles around vertex " +
                                std::to_string(vertex) + " link to triangle " +
                                std::to_string(*next) +
                                ", which does not exist; run tinbase "
                                "check");
    TB_RETURN_IF_ERROR(read.status());
    if (CornerOf(*read, vertex) < 0)
      return Status::Corruption("surface '" + surface.name + "': triangle " +
                                std::to_string(*next) + " is linked around vertex " +
                                std::to_string(vertex) +
                                " but does not have it; run tinbase "
                                "check");
    row = *read;
    ids->push_back(*next);
    rows->push_back(row);
  }
  return Status::Corruption("surface '" + surface.name + "': the triangles around vertex " +
                            std::to_string(vertex) + " do not close; run tinbase check");
}

}  // namespace

Result<VertexStar> StarOf(Store& store, const SurfaceInfo& surface, int64_t vertex) {
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  MeshTables tables(store.db(), surface);
  VertexStar star;
  star.vertex = vertex;
  TB_ASSIGN_OR_RETURN(star.row, tables.Vertex(vertex));
  // No index leads from a vertex to its triangles; the locator walks to one holding its
  // position, and every triangle holding a vertex's position has that vertex as a corner.
  PointLocator locator(store, surface);
  Result<Location> at = locator.LocateTriangle(star.row.x, star.row.y);
  if (at.status().code() == StatusCode::kNotFound)
    return Status::NotFound("vertex " + std::to_string(vertex) + " of surface '" + surface.name +
                            "' is a corner of no triangle");
  TB_RETURN_IF_ERROR(at.status());
  TB_ASSIGN_OR_RETURN(const TriangleRow first, tables.Triangle(at->triangle));
  if (CornerOf(first, vertex) < 0)
    return Status::NotFound("vertex " + std::to_string(vertex) + " of surface '" + surface.name +
                            "' is a corner of no triangle (triangle " +
                            std::to_string(at->triangle) + " covers it)");
  std::vector<int64_t> ccw_ids, cw_ids;
  std::vector<TriangleRow> ccw_rows, cw_rows;
  TB_ASSIGN_OR_RETURN(const bool closed,
                      Turn(tables, surface, vertex, at->triangle, first, 1, &ccw_ids, &ccw_rows));
  if (!closed) {
    TB_RETURN_IF_ERROR(
        Turn(tables, surface, vertex, at->triangle, first, 2, &cw_ids, &cw_rows).status());
  }
  std::reverse(cw_ids.begin(), cw_ids.end());
  std::reverse(cw_rows.begin(), cw_rows.end());
  std::vector<TriangleRow> rows = cw_rows;
  star.triangles = cw_ids;
  star.triangles.push_back(at->triangle);
  rows.push_back(first);
  star.triangles.insert(star.triangles.end(), ccw_ids.begin(), ccw_ids.end());
  rows.insert(rows.end(), ccw_rows.begin(), ccw_rows.end());
  star.boundary = !closed;
  // Triangle (vertex, a, b) counter-clockwise spans from a to b around the vertex.
  for (const TriangleRow& row : rows) {
    const int k = CornerOf(row, vertex);
    star.links.push_back(row.v[(k + 1) % 3]);
  }
  if (star.boundary) {
    const TriangleRow& last = rows.back();
    star.links.push_back(last.v[(CornerOf(last, vertex) + 2) % 3]);
  }
  return star;
}

Result<TriangleNeighbours> NeighboursOf(Store& store, const SurfaceInfo& surface,
                                        int64_t triangle) {
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  MeshTables tables(store.db(), surface);
  TriangleNeighbours out;
  out.triangle = triangle;
  TB_ASSIGN_OR_RETURN(out.row, tables.Triangle(triangle));
  if (out.row.tag) {
    Result<std::string> value = tables.TagValue(*out.row.tag);
    if (value.ok()) {
      out.tag = *value;
    } else if (value.status().code() != StatusCode::kNotFound) {
      return value.status();  // an unknown tag is CheckStore's unknown-tag, not ours
    }
  }
  std::array<VertexRow, 3> corners;
  for (int i = 0; i < 3; ++i) {
    TB_ASSIGN_OR_RETURN(corners[i], tables.Vertex(out.row.v[i]));
  }
  for (int i = 0; i < 3; ++i) {
    SharedEdge& e = out.edges[i];
    const int a = (i + 1) % 3, b = (i + 2) % 3;
    e.neighbour = out.row.n[i];
    e.vertices = {out.row.v[a], out.row.v[b]};
    e.ends = {corners[a], corners[b]};
    TB_ASSIGN_OR_RETURN(const std::vector<int64_t> owners,
                        tables.Owners(std::min(e.vertices[0], e.vertices[1]),
                                      std::max(e.vertices[0], e.vertices[1])));
    e.constrained = !owners.empty();
  }
  return out;
}

}  // namespace tinbase
