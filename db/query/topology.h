// Topology queries over a stored surface: the star of a vertex (its triangles and neighbouring
// vertices in turn around it) and a triangle's neighbours with the edges they share. (The
// triangles of a window or of a feature are SelectSurface's, db/query/surface_selection.h.)
//
// Star and neighbours read only the rows around the vertex or triangle, through MeshTables, in
// one read snapshot. Thread-safety: one call per Store at a time.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "db/mesh/mesh_rows.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

// A vertex and everything around it, counter-clockwise.
struct VertexStar {
  int64_t vertex = 0;
  VertexRow row;
  // The triangles around the vertex counter-clockwise; on the boundary from the one on the
  // clockwise end of the fan to the one on the counter-clockwise end.
  std::vector<int64_t> triangles;
  // The vertices joined to it by an edge, counter-clockwise: links[i] and links[i + 1] are the
  // other corners of triangles[i]. Closed (an inner vertex): one per triangle, links[0] closing
  // the ring; on the boundary, one more than there are triangles.
  std::vector<int64_t> links;
  bool boundary = false;  // the vertex lies on the surface's boundary
};

// The star of vertex `vertex` of `surface`. NotFound naming the vertex and the surface when it is
// not a vertex of the surface, or is a corner of no triangle; Corruption when the links around
// it contradict the triangles' corners.
Result<VertexStar> StarOf(Store& store, const SurfaceInfo& surface, int64_t vertex);

// One edge of a triangle and what lies across it.
struct SharedEdge {
  std::optional<int64_t> neighbour;   // nullopt on the boundary
  std::array<int64_t, 2> vertices{};  // the edge's ends, in the triangle's counter-clockwise order
  std::array<VertexRow, 2> ends;      // their rows
  bool constrained = false;           // a constrained edge (a feature's ring or a breakline)
};

// A triangle and its three edges; edges[i] is opposite row.v[i] (TriangleRow::n).
struct TriangleNeighbours {
  int64_t triangle = 0;
  TriangleRow row;
  std::optional<std::string> tag;  // the tag's value
  std::array<SharedEdge, 3> edges;
};

// Triangle `triangle` of `surface` with its neighbours and the edges they share. NotFound
// naming the triangle and the surface when it is not one of its triangles.
Result<TriangleNeighbours> NeighboursOf(Store& store, const SurfaceInfo& surface, int64_t triangle);

}  // namespace tinbase
