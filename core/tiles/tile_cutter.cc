// TileCutter: see tile_cutter.h.
#include "core/tiles/tile_cutter.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "core/geometry/predicates.h"
#include "core/tiles/tile_mesh_builder.h"

namespace tinbase {

namespace {

// The four lines that bound a tile, in the order they clip.
enum ClipLine : int { kWest = 0, kEast = 1, kSouth = 2, kNorth = 3 };
constexpr int kNoLine = -1;

using ClipPoint = TilePoint;

// One vertex of a polygon being clipped, with where the edge leaving it lies: on TIN edge
// (edge_a, edge_b), or on a clip line.
struct PolygonVertex {
  ClipPoint point;
  uint32_t edge_a = 0, edge_b = 0;
  int edge_line = kNoLine;
};

double LineValue(const TileRect& r, int line) {
  switch (line) {
    case kWest:
      return r.west;
    case kEast:
      return r.east;
    case kSouth:
      return r.south;
    default:
      return r.north;
  }
}

bool IsLongitudeLine(int line) { return line == kWest || line == kEast; }

bool Inside(const ClipPoint& p, const TileRect& r, int line) {
  switch (line) {
    case kWest:
      return p.lon >= r.west;
    case kEast:
      return p.lon <= r.east;
    case kSouth:
      return p.lat >= r.south;
    default:
      return p.lat <= r.north;
  }
}

Ecef Lerp(const Ecef& a, const Ecef& b, double t) {
  return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

class TileClipper {
 public:
  TileClipper(const GeoSurface& surface, const std::vector<TinVertex>& vertices,
              const TileRect& rect, const std::vector<uint32_t>& candidates)
      : s_(surface), vertices_(vertices), rect_(rect), candidates_(candidates) {}

  ClipPoint VertexPoint(uint32_t v) const {
    const TinVertex& p = vertices_[v];
    return {p.x, p.y, p.z, NormalOf(v)};
  }

  // Where TIN edge (a, b) crosses clip line `line`, computed from the edge alone.
  ClipPoint EdgeCrossing(uint32_t a, uint32_t b, int line) const {
    if (a > b) std::swap(a, b);
    const TinVertex& pa = vertices_[a];
    const TinVertex& pb = vertices_[b];
    const double value = LineValue(rect_, line);
    const bool lon_line = IsLongitudeLine(line);
    const double ca = lon_line ? pa.x : pa.y;
    const double cb = lon_line ? pb.x : pb.y;
    if (ca == value) return VertexPoint(a);
    if (cb == value) return VertexPoint(b);
    const double t = (value - ca) / (cb - ca);
    ClipPoint out;
    out.lon = lon_line ? value : pa.x + t * (pb.x - pa.x);
    out.lat = lon_line ? pa.y + t * (pb.y - pa.y) : value;
    out.h = pa.z + t * (pb.z - pa.z);
    if (!s_.normals.empty()) out.normal = Lerp(s_.normals[a], s_.normals[b], t);
    return out;
  }

  // A corner of the tile, its height from the lowest-numbered visible triangle holding it.
  ClipPoint Corner(int line1, int line2) const {
    const int lon_line = IsLongitudeLine(line1) ? line1 : line2;
    const int lat_line = IsLongitudeLine(line1) ? line2 : line1;
    ClipPoint out;
    out.lon = LineValue(rect_, lon_line);
    out.lat = LineValue(rect_, lat_line);
    const Point2 q{out.lon, out.lat};
    for (uint32_t t : candidates_) {  // ascending
      const auto& v = s_.tin.triangles[t].v;
      const TinVertex &a = vertices_[v[0]], &b = vertices_[v[1]], &c = vertices_[v[2]];
      const Point2 pa{a.x, a.y}, pb{b.x, b.y}, pc{c.x, c.y};
      if (Orientation(pa, pb, q) < 0 || Orientation(pb, pc, q) < 0 || Orientation(pc, pa, q) < 0)
        continue;
      const double area = (pb.x - pa.x) * (pc.y - pa.y) - (pb.y - pa.y) * (pc.x - pa.x);
      const double wa = ((pb.x - q.x) * (pc.y - q.y) - (pb.y - q.y) * (pc.x - q.x)) / area;
      const double wb = ((pc.x - q.x) * (pa.y - q.y) - (pc.y - q.y) * (pa.x - q.x)) / area;
      const double wc = 1 - wa - wb;
      out.h = wa * a.z + wb * b.z + wc * c.z;
      if (!s_.normals.empty())
        for (int k = 0; k < 3; ++k)
          out.normal[k] =
              wa * s_.normals[v[0]][k] + wb * s_.normals[v[1]][k] + wc * s_.normals[v[2]][k];
      return out;
    }
    return out;  // not reached for a corner inside a clipped triangle
  }

  // The triangle clipped to the tile: a convex polygon, empty when it misses the tile.
  std::vector<ClipPoint> Clip(uint32_t t) const {
    const auto& v = s_.tin.triangles[t].v;
    std::vector<PolygonVertex> polygon;
    for (int i = 0; i < 3; ++i)
      polygon.push_back({VertexPoint(v[i]), v[i], v[(i + 1) % 3], kNoLine});
    for (int line : {kWest, kEast, kSouth, kNorth}) {
      polygon = ClipAgainst(polygon, line);
      if (polygon.empty()) break;
    }
    std::vector<ClipPoint> out;
    for (const PolygonVertex& p : polygon) out.push_back(p.point);
    return out;
  }

 private:
  Ecef NormalOf(uint32_t v) const { return s_.normals.empty() ? Ecef{} : s_.normals[v]; }

  ClipPoint Crossing(const PolygonVertex& from, int line) const {
    if (from.edge_line != kNoLine) return Corner(from.edge_line, line);
    return EdgeCrossing(from.edge_a, from.edge_b, line);
  }

  std::vector<PolygonVertex> ClipAgainst(const std::vector<PolygonVertex>& in, int line) const {
    std::vector<PolygonVertex> out;
    for (size_t i = 0; i < in.size(); ++i) {
      const PolygonVertex& p = in[i];
      const PolygonVertex& q = in[(i + 1) % in.size()];
      const bool p_in = Inside(p.point, rect_, line);
      const bool q_in = Inside(q.point, rect_, line);
      if (p_in) out.push_back(p);
      if (p_in && !q_in) {
        out.push_back({Crossing(p, line), 0, 0, line});
      } else if (!p_in && q_in) {
        out.push_back({Crossing(p, line), p.edge_a, p.edge_b, p.edge_line});
      }
    }
    return out;
  }

  const GeoSurface& s_;
  const std::vector<TinVertex>& vertices_;
  TileRect rect_;
  const std::vector<uint32_t>& candidates_;
};

}  // namespace

std::vector<Ecef> VertexNormals(const Tin& tin) {
  std::vector<Ecef> ecef;
  ecef.reserve(tin.vertices.size());
  for (const TinVertex& v : tin.vertices) ecef.push_back(ToEcef(v.x, v.y, v.z));
  std::vector<Ecef> normals(tin.vertices.size(), Ecef{});
  for (const TinTriangle& t : tin.triangles) {
    const Ecef &a = ecef[t.v[0]], &b = ecef[t.v[1]], &c = ecef[t.v[2]];
    const Ecef ab = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const Ecef ac = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    // Twice the area times the unit normal: larger triangles weigh more.
    const Ecef n = {ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2],
                    ab[0] * ac[1] - ab[1] * ac[0]};
    for (uint32_t v : t.v)
      for (int k = 0; k < 3; ++k) normals[v][k] += n[k];
  }
  for (size_t i = 0; i < normals.size(); ++i) {
    Ecef& n = normals[i];
    double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(length > 0)) {  // an unused vertex: the ellipsoid's up
      n = ecef[i];
      length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    for (double& c : n) c /= length;
  }
  return normals;
}

namespace {

// `value` moved exactly onto the nearest tile line of a level when it is within half a
// quantisation step of it, so that a vertex that any tile would put on its edge lies on that
// edge in the neighbour's eyes too. `origin` is -180 or -90.
double SnapToTileLine(double value, double origin, int level) {
  const double size = TileDegrees(level);
  const double line = std::round((value - origin) / size);
  const double snapped = origin + line * size;  // as RectOf computes it
  return std::abs(value - snapped) < size / kQuantizedMax / 2 ? snapped : value;
}

}  // namespace

TileCutter::TileCutter(const GeoSurface& surface, int level)
    : surface_(surface), vertices_(surface.tin.vertices) {
  for (TinVertex& v : vertices_) {
    v.x = SnapToTileLine(v.x, -180.0, level);
    v.y = SnapToTileLine(v.y, -90.0, level);
  }
  const Tin& tin = surface.tin;
  for (uint32_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    if (!tri.visible) continue;
    const TinVertex &a = vertices_[tri.v[0]], &b = vertices_[tri.v[1]], &c = vertices_[tri.v[2]];
    const TileRange range =
        TilesMeeting(level, std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}),
                     std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}));
    for (int64_t y = range.y0; y <= range.y1; ++y)
      for (int64_t x = range.x0; x <= range.x1; ++x) triangles_of_tile_[{level, x, y}].push_back(t);
  }
}

std::vector<TileKey> TileCutter::Tiles() const {
  std::vector<TileKey> keys;
  for (const auto& [key, triangles] : triangles_of_tile_) keys.push_back(key);
  return keys;
}

std::optional<QuantizedMesh> TileCutter::Cut(const TileKey& key) const {
  auto it = triangles_of_tile_.find(key);
  if (it == triangles_of_tile_.end()) return std::nullopt;
  const TileRect rect = RectOf(key);
  TileClipper clipper(surface_, vertices_, rect, it->second);
  TileMeshBuilder builder(rect, surface_.min_height, surface_.max_height,
                          !surface_.normals.empty());
  for (uint32_t t : it->second) {
    const std::vector<ClipPoint> polygon = clipper.Clip(t);
    if (polygon.size() >= 3) builder.AddPolygon(polygon);
  }
  return builder.Finish();
}

std::vector<uint8_t> TileCutter::WaterMask(const TileKey& key, int32_t water_tag) const {
  constexpr int kSize = 256;
  std::vector<uint8_t> mask(kSize * kSize, 0);
  auto it = triangles_of_tile_.find(key);
  if (it != triangles_of_tile_.end() && water_tag != kNoTag) {
    const TileRect r = RectOf(key);
    const double step_x = (r.east - r.west) / kSize;
    const double step_y = (r.north - r.south) / kSize;
    for (uint32_t t : it->second) {
      const TinTriangle& tri = surface_.tin.triangles[t];
      if (tri.tag != water_tag) continue;
      const Point2 a{vertices_[tri.v[0]].x, vertices_[tri.v[0]].y};
      const Point2 b{vertices_[tri.v[1]].x, vertices_[tri.v[1]].y};
      const Point2 c{vertices_[tri.v[2]].x, vertices_[tri.v[2]].y};
      const auto col = [&](double lon) { return (lon - r.west) / step_x - 0.5; };
      const auto row = [&](double lat) { return (r.north - lat) / step_y - 0.5; };
      const int c0 = std::max(0, static_cast<int>(std::floor(col(std::min({a.x, b.x, c.x})))));
      const int c1 =
          std::min(kSize - 1, static_cast<int>(std::ceil(col(std::max({a.x, b.x, c.x})))));
      const int r0 = std::max(0, static_cast<int>(std::floor(row(std::max({a.y, b.y, c.y})))));
      const int r1 =
          std::min(kSize - 1, static_cast<int>(std::ceil(row(std::min({a.y, b.y, c.y})))));
      for (int y = r0; y <= r1; ++y)
        for (int x = c0; x <= c1; ++x) {
          const Point2 q{r.west + (x + 0.5) * step_x, r.north - (y + 0.5) * step_y};
          if (Orientation(a, b, q) >= 0 && Orientation(b, c, q) >= 0 && Orientation(c, a, q) >= 0)
            mask[static_cast<size_t>(y) * kSize + x] = 255;
        }
    }
  }
  if (std::all_of(mask.begin(), mask.end(), [&](uint8_t m) { return m == mask[0]; }))
    return {mask[0]};
  return mask;
}

}  // namespace tinbase
