// LineWalk: a polyline followed across a triangulation by its neighbour links, recording every
// point where it crosses a triangle edge or passes through a vertex, with z interpolated there
// (the stations of a terrain profile).
//
// A straight walk (Devillers, Pion, Teillaud, "Walking in a triangulation"): every decision is
// an exact orientation test (core/geometry/predicates.h) against the stored coordinates of the
// segment's ends and the triangle's corners, never against a computed crossing point, so lines
// that run through vertices or along edges are followed without tolerances. Only the reported
// crossing points and their z are rounded. The triangles are read one at a time through a
// callback, so the walk reads O(crossings) rows whatever the surface's size.
// Stateless; thread-safe when the reader is.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/predicates.h"

namespace tinbase {

// A triangle as the walk reads it.
struct WalkTriangle {
  std::array<int64_t, 3> v{};               // vertex ids, counter-clockwise in plan view
  std::array<Point2, 3> p;                  // their plan positions
  std::array<double, 3> z{};                // their heights
  std::array<std::optional<int64_t>, 3> n;  // n[i]: the triangle across the edge opposite v[i]
};

// Reads triangle `id`; its errors end the walk and are returned as they are.
using WalkTriangleReader = std::function<Result<WalkTriangle>(int64_t id)>;

enum class StationKind {
  kStart,   // the line's first point
  kEdge,    // a crossing of a triangle edge
  kVertex,  // the line passes through a vertex of the surface
  kBend,    // one of the line's inner points
  kEnd,     // the line's last point
};
const char* StationKindName(StationKind kind);  // "start", "edge", "vertex", "bend", "end"

struct Station {
  double distance = 0;  // along the line from its first point, in plan view
  double x = 0;
  double y = 0;
  double z = 0;
  StationKind kind = StationKind::kStart;
};

// The stations in order along the line, and the triangle of each stretch between two stations:
// triangles[i] holds the stretch from stations[i] to stations[i + 1] (one of the two triangles
// beside it when the stretch runs along an edge).
struct LineWalk {
  std::vector<Station> stations;
  std::vector<int64_t> triangles;  // stations.size() - 1 entries
};

// Follows `line` from `start_triangle`. Repeated consecutive points are skipped. Returns the
// stations and stretches. InvalidArgument "the line leaves the surface at (x, y) on its way to
// point k" (k 1-based) when it crosses the boundary; Corruption when the links the walk follows
// contradict the geometry; the reader's errors.
// REQUIRES: line.size() >= 2, with two distinct points; finite coordinates; `start_triangle`
// holds line[0] (on its boundary counts).
Result<LineWalk> WalkLine(const std::vector<Point2>& line, int64_t start_triangle,
                          const WalkTriangleReader& read);

// z of the plane through triangle `t` at (x, y), by barycentric coordinates relative to its first
// corner (large map coordinates would otherwise cancel away the small differences that matter).
double InterpolateZ(const WalkTriangle& t, double x, double y);

}  // namespace tinbase
