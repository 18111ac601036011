#include "core/geometry/polygon.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <tuple>

#include "core/base/number_text.h"

namespace tinbase {

namespace {

std::string FormatNumber(double v) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), v);
  return ec == std::errc() ? std::string(buffer, end) : std::string("?");
}

// A ring as validation sees it: open, without consecutive repeats, remembering where each
// vertex was in the input so messages name the user's vertex numbers.
struct CleanRing {
  Ring points;
  std::vector<size_t> original;
};

struct Segment {
  uint32_t ring;
  uint32_t index;  // edge index: from points[index] to points[(index + 1) % size]
  Point2 a, b;
  double min_x, max_x, min_y, max_y;
};

enum class Contact { kNone, kCross, kTouch, kOverlap };
struct Intersection {
  Contact contact = Contact::kNone;
  Point2 at;
};

std::string RingVertex(uint32_t ring, size_t vertex) {
  return "ring " + std::to_string(ring) + ", vertex " + std::to_string(vertex);
}

Status CheckRawRing(uint32_t r, const Ring& ring) {
  for (size_t v = 0; v < ring.size(); ++v) {
    if (!std::isfinite(ring[v].x) || !std::isfinite(ring[v].y))
      return Status::InvalidArgument(RingVertex(r, v) + ": coordinate is not finite " +
                                     FormatPoint(ring[v]));
    // Beyond 1e15 no CRS has room, and the orientation tests' products would overflow
    // (core/base/number_text.h); a 1e300 vertex was once cut to the data area and accepted.
    if (CheckNumber(ring[v].x) || CheckNumber(ring[v].y))
      return Status::InvalidArgument(RingVertex(r, v) + ": coordinate " + FormatPoint(ring[v]) +
                                     " is larger in magnitude than 1e15");
  }
  if (ring.size() < 2 || !SamePoint(ring.front(), ring.back())) {
    std::string msg = "ring " + std::to_string(r) + ": ring is not closed";
    if (!ring.empty())
      msg += " (vertex 0 " + FormatPoint(ring.front()) + ", last vertex " +
             std::to_string(ring.size() - 1) + " " + FormatPoint(ring.back()) + ")";
    return Status::InvalidArgument(msg);
  }
  return Status::Ok();
}

Result<CleanRing> Clean(uint32_t r, const Ring& ring) {
  TB_RETURN_IF_ERROR(CheckRawRing(r, ring));
  CleanRing clean;
  for (size_t v = 0; v + 1 < ring.size(); ++v) {
    if (!clean.points.empty() && SamePoint(clean.points.back(), ring[v])) continue;
    clean.points.push_back(ring[v]);
    clean.original.push_back(v);
  }
  if (clean.points.size() > 1 && SamePoint(clean.points.back(), clean.points.front())) {
    clean.points.pop_back();
    clean.original.pop_back();
  }
  Ring sorted = clean.points;
  std::sort(sorted.begin(), sorted.end(), [](const Point2& p, const Point2& q) {
    return p.x < q.x || (p.x == q.x && p.y < q.y);
  });
  const size_t distinct = std::unique(sorted.begin(), sorted.end(), SamePoint) - sorted.begin();
  if (distinct < 3)
    return Status::InvalidArgument("ring " + std::to_string(r) +
                                   ": fewer than 3 distinct points (" + std::to_string(distinct) +
                                   ")");
  return clean;
}

// REQUIRES: c is collinear with ab.
bool WithinBox(const Point2& a, const Point2& b, const Point2& c) {
  return std::min(a.x, b.x) <= c.x && c.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= c.y &&
         c.y <= std::max(a.y, b.y);
}

// How two segments that share no ring vertex meet. The crossing point is computed in doubles;
// it only goes into a message, every decision is made by the exact orientation tests.
Intersection Intersect(const Segment& s, const Segment& t) {
  const int o1 = Orientation(s.a, s.b, t.a), o2 = Orientation(s.a, s.b, t.b);
  const int o3 = Orientation(t.a, t.b, s.a), o4 = Orientation(t.a, t.b, s.b);
  if (o1 * o2 < 0 && o3 * o4 < 0) {
    const double d = (s.b.x - s.a.x) * (t.b.y - t.a.y) - (s.b.y - s.a.y) * (t.b.x - t.a.x);
    const double u = ((t.a.x - s.a.x) * (t.b.y - t.a.y) - (t.a.y - s.a.y) * (t.b.x - t.a.x)) / d;
    return {Contact::kCross, {s.a.x + u * (s.b.x - s.a.x), s.a.y + u * (s.b.y - s.a.y)}};
  }
  if (o1 == 0 && o2 == 0) {
    // Collinear: compare the projections on the dominant axis.
    const bool use_x = std::abs(s.b.x - s.a.x) >= std::abs(s.b.y - s.a.y);
    const auto key = [use_x](const Point2& p) { return use_x ? p.x : p.y; };
    const double lo = std::max(std::min(key(s.a), key(s.b)), std::min(key(t.a), key(t.b)));
    const double hi = std::min(std::max(key(s.a), key(s.b)), std::max(key(t.a), key(t.b)));
    if (lo > hi) return {};
    Point2 at = s.a;
    for (const Point2& p : {s.a, s.b, t.a, t.b})
      if (key(p) == lo) at = p;
    return {lo < hi ? Contact::kOverlap : Contact::kTouch, at};
  }
  if (o1 == 0 && WithinBox(s.a, s.b, t.a)) return {Contact::kTouch, t.a};
  if (o2 == 0 && WithinBox(s.a, s.b, t.b)) return {Contact::kTouch, t.b};
  if (o3 == 0 && WithinBox(t.a, t.b, s.a)) return {Contact::kTouch, s.a};
  if (o4 == 0 && WithinBox(t.a, t.b, s.b)) return {Contact::kTouch, s.b};
  return {};
}

std::string EdgeName(const CleanRing& ring, uint32_t index) {
  const size_t next = (index + 1) % ring.points.size();
  return std::to_string(ring.original[index]) + "-" + std::to_string(ring.original[next]);
}

// Two different rings meeting at one point: allowed, unless such contacts close a loop.
struct Touch {
  Point2 at;
  uint32_t ring;
  friend bool operator<(const Touch& a, const Touch& b) {
    return std::tie(a.at.x, a.at.y, a.ring) < std::tie(b.at.x, b.at.y, b.ring);
  }
};

// The problem, if any, between two segments of the polygon. Consecutive edges of one ring
// share a vertex by construction; they are wrong only when the ring turns back on itself.
// Point contacts between different rings are added to `touches`.
std::optional<Status> CheckPair(const std::vector<CleanRing>& rings, const Segment& s0,
                                const Segment& t0, std::vector<Touch>& touches) {
  const Segment& s = std::tie(s0.ring, s0.index) < std::tie(t0.ring, t0.index) ? s0 : t0;
  const Segment& t = &s == &s0 ? t0 : s0;
  const CleanRing& rs = rings[s.ring];
  if (s.ring == t.ring) {
    const uint32_t m = static_cast<uint32_t>(rs.points.size());
    const bool t_follows = t.index == (s.index + 1) % m;
    const bool s_follows = s.index == (t.index + 1) % m;
    if (t_follows || s_follows) {
      const Segment& first = t_follows ? s : t;
      const Segment& second = t_follows ? t : s;
      const Point2 &a = first.a, &q = first.b, &c = second.b;
      const bool folds =
          Orientation(a, q, c) == 0 && (a.x - q.x) * (c.x - q.x) + (a.y - q.y) * (c.y - q.y) > 0;
      if (!folds) return std::nullopt;
      return Status::InvalidArgument(RingVertex(s.ring, rs.original[second.index]) +
                                     ": ring folds back on itself at " + FormatPoint(q));
    }
  }
  const Intersection hit = Intersect(s, t);
  if (hit.contact == Contact::kNone) return std::nullopt;
  const std::string where = RingVertex(s.ring, rs.original[s.index]) + ": ";
  const std::string edges = " (edges " + EdgeName(rs, s.index) + " and " +
                            (s.ring == t.ring ? "" : "ring " + std::to_string(t.ring) + " ") +
                            EdgeName(rings[t.ring], t.index) + ")";
  if (s.ring == t.ring) {
    const char* what = hit.contact == Contact::kCross   ? "ring crosses itself at "
                       : hit.contact == Contact::kTouch ? "ring touches itself at "
                                                        : "ring runs along itself at ";
    return Status::InvalidArgument(where + what + FormatPoint(hit.at) + edges);
  }
  if (hit.contact == Contact::kTouch) {
    touches.push_back({hit.at, s.ring});
    touches.push_back({hit.at, t.ring});
    return std::nullopt;
  }
  const char* what = hit.contact == Contact::kCross ? "crosses ring " : "shares an edge with ring ";
  return Status::InvalidArgument(where + what + std::to_string(t.ring) + " at " +
                                 FormatPoint(hit.at) + edges);
}

// A sweep over x: segments sorted by their left end, each compared only with the segments that
// start before it ends. Near-linear for map polygons, whose edges are short against the ring.
Status CheckIntersections(const std::vector<CleanRing>& rings, std::vector<Touch>& touches) {
  std::vector<Segment> segments;
  for (uint32_t r = 0; r < rings.size(); ++r) {
    const Ring& p = rings[r].points;
    for (uint32_t i = 0; i < p.size(); ++i) {
      const Point2& a = p[i];
      const Point2& b = p[(i + 1) % p.size()];
      segments.push_back({r, i, a, b, std::min(a.x, b.x), std::max(a.x, b.x), std::min(a.y, b.y),
                          std::max(a.y, b.y)});
    }
  }
  std::sort(segments.begin(), segments.end(), [](const Segment& s, const Segment& t) {
    return std::tie(s.min_x, s.ring, s.index) < std::tie(t.min_x, t.ring, t.index);
  });
  // Report the problem a reader meets first along the rings, not the one the sweep meets first.
  using Key = std::pair<std::pair<uint32_t, uint32_t>, std::pair<uint32_t, uint32_t>>;
  std::optional<std::pair<Key, Status>> first;
  for (size_t i = 0; i < segments.size(); ++i) {
    const Segment& s = segments[i];
    for (size_t j = i + 1; j < segments.size() && segments[j].min_x <= s.max_x; ++j) {
      const Segment& t = segments[j];
      if (t.min_y > s.max_y || t.max_y < s.min_y) continue;
      if (auto problem = CheckPair(rings, s, t, touches)) {
        const std::pair<uint32_t, uint32_t> ks{s.ring, s.index}, kt{t.ring, t.index};
        const Key key = ks < kt ? Key{ks, kt} : Key{kt, ks};
        if (!first || key < first->first) first.emplace(key, std::move(*problem));
      }
    }
  }
  return first ? first->second : Status::Ok();
}

// Rings may touch at points, but the rings and their contact points must not form a loop: a
// loop (a hole touching the shell twice, two holes touching each other twice, a chain of holes
// from shell to shell) cuts the interior apart, which OGC forbids (GEOS: "Interior is
// disconnected"). Union-find over rings and contact points finds the edge that closes a loop.
Status CheckInteriorConnected(uint32_t ring_count, std::vector<Touch> touches) {
  std::sort(touches.begin(), touches.end());
  touches.erase(std::unique(touches.begin(), touches.end(),
                            [](const Touch& a, const Touch& b) {
                              return SamePoint(a.at, b.at) && a.ring == b.ring;
                            }),
                touches.end());
  std::vector<uint32_t> parent(ring_count + touches.size());
  for (uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  const auto find = [&parent](uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  uint32_t node = ring_count;  // touches[k] at a new point gets the next node id
  for (size_t k = 0; k < touches.size(); ++k) {
    if (k > 0 && !SamePoint(touches[k].at, touches[k - 1].at)) ++node;
    const uint32_t a = find(touches[k].ring), b = find(node);
    if (a == b)
      return Status::InvalidArgument("ring " + std::to_string(touches[k].ring) + ": touches at " +
                                     FormatPoint(touches[k].at) +
                                     " rings it already touches elsewhere, cutting the "
                                     "polygon's interior apart");
    parent[a] = b;
  }
  return Status::Ok();
}

// A point of `inner` that is not on `outer`'s boundary (a vertex, else an edge midpoint), with
// the input vertex number to name; nullopt when all of them lie on it.
std::optional<std::pair<Point2, size_t>> PointOffRing(const CleanRing& inner, const Ring& outer) {
  const Ring& p = inner.points;
  for (size_t i = 0; i < p.size(); ++i)
    if (LocateInRing(outer, p[i]) != PointInPolygon::kBoundary) return {{p[i], inner.original[i]}};
  for (size_t i = 0; i < p.size(); ++i) {
    const Point2& a = p[i];
    const Point2& b = p[(i + 1) % p.size()];
    const Point2 mid{(a.x + b.x) / 2, (a.y + b.y) / 2};
    if (LocateInRing(outer, mid) != PointInPolygon::kBoundary) return {{mid, inner.original[i]}};
  }
  return std::nullopt;
}

// With no crossings between rings, one point of a hole tells where the whole hole lies.
Status CheckHoles(const std::vector<CleanRing>& rings) {
  const Ring& shell = rings[0].points;
  for (uint32_t h = 1; h < rings.size(); ++h) {
    const auto probe = PointOffRing(rings[h], shell);
    if (!probe)
      return Status::InvalidArgument("ring " + std::to_string(h) +
                                     ": hole lies on its shell's boundary");
    if (LocateInRing(shell, probe->first) == PointInPolygon::kOutside)
      return Status::InvalidArgument(RingVertex(h, probe->second) +
                                     ": hole lies outside its shell (ring 0) at " +
                                     FormatPoint(probe->first));
  }
  for (uint32_t h = 1; h < rings.size(); ++h) {
    for (uint32_t k = 1; k < rings.size(); ++k) {
      if (h == k) continue;
      const auto probe = PointOffRing(rings[h], rings[k].points);
      if (!probe)
        return Status::InvalidArgument("ring " + std::to_string(h) + ": hole coincides with ring " +
                                       std::to_string(k));
      if (LocateInRing(rings[k].points, probe->first) == PointInPolygon::kInside)
        return Status::InvalidArgument(RingVertex(h, probe->second) + ": hole lies inside hole " +
                                       std::to_string(k) + " at " + FormatPoint(probe->first));
    }
  }
  return Status::Ok();
}

}  // namespace

EdgeRay RayTest(const Point2& a, const Point2& b, const Point2& p) {
  const bool a_above = a.y > p.y, b_above = b.y > p.y;
  if (a_above == b_above) {
    // Both ends on one side: p can only be on the edge when the edge is horizontal at p.y.
    if (a.y == p.y && b.y == p.y && std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x))
      return EdgeRay::kOnEdge;
    if ((a.y == p.y && a.x == p.x) || (b.y == p.y && b.x == p.x)) return EdgeRay::kOnEdge;
    return EdgeRay::kMiss;
  }
  const int o = Orientation(a, b, p);
  if (o == 0) return EdgeRay::kOnEdge;  // collinear and within the edge's y-range
  // The ray crosses when p is left of an upward edge or right of a downward one.
  return (b_above ? o > 0 : o < 0) ? EdgeRay::kCross : EdgeRay::kMiss;
}

PointInPolygon LocateInRing(const Ring& ring, const Point2& p) {
  bool inside = false;
  for (size_t i = 0; i < ring.size(); ++i) {
    switch (RayTest(ring[i], ring[(i + 1) % ring.size()], p)) {
      case EdgeRay::kOnEdge:
        return PointInPolygon::kBoundary;
      case EdgeRay::kCross:
        inside = !inside;
        break;
      case EdgeRay::kMiss:
        break;
    }
  }
  return inside ? PointInPolygon::kInside : PointInPolygon::kOutside;
}

double SignedDoubleArea(const Ring& ring) {
  double sum = 0;
  for (size_t i = 0; i < ring.size(); ++i) {
    const Point2& a = ring[i];
    const Point2& b = ring[(i + 1) % ring.size()];
    sum += (a.x - b.x) * (a.y + b.y);
  }
  return sum;
}

std::string FormatPoint(const Point2& p) {
  std::string out = "(";  // appended piecewise: GCC 12 warns falsely on "(" + std::string
  out += FormatNumber(p.x);
  out += ", ";
  out += FormatNumber(p.y);
  out += ')';
  return out;
}

Result<Polygon> MakeValidPolygon(const std::vector<Ring>& rings) {
  if (rings.empty()) return Status::InvalidArgument("polygon has no rings");
  std::vector<CleanRing> clean;
  for (uint32_t r = 0; r < rings.size(); ++r) {
    TB_ASSIGN_OR_RETURN(CleanRing ring, Clean(r, rings[r]));
    clean.push_back(std::move(ring));
  }
  std::vector<Touch> touches;
  TB_RETURN_IF_ERROR(CheckIntersections(clean, touches));
  TB_RETURN_IF_ERROR(CheckHoles(clean));
  TB_RETURN_IF_ERROR(CheckInteriorConnected(static_cast<uint32_t>(clean.size()), touches));
  Polygon polygon;
  polygon.shell = std::move(clean[0].points);
  if (SignedDoubleArea(polygon.shell) < 0) std::reverse(polygon.shell.begin(), polygon.shell.end());
  for (size_t h = 1; h < clean.size(); ++h) {
    Ring hole = std::move(clean[h].points);
    if (SignedDoubleArea(hole) > 0) std::reverse(hole.begin(), hole.end());
    polygon.holes.push_back(std::move(hole));
  }
  return polygon;
}

}  // namespace tinbase
