#include "core/measure/contour_lines.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <unordered_map>

namespace tinbase {

namespace {

constexpr int64_t kMaxLevels = 100000;

uint64_t EdgeKey(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<uint64_t>(a) << 32) | b;
}

std::string Text(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Where edge (a, b) crosses `level`, computed from the lower-indexed end so both triangles of the
// edge get the same point. REQUIRES: one end below the level and the other at or above it.
Point2 Crossing(const Tin& tin, uint32_t a, uint32_t b, double level) {
  if (a > b) std::swap(a, b);
  const TinVertex& p = tin.vertices[a];
  const TinVertex& q = tin.vertices[b];
  const double f = (level - p.z) / (q.z - p.z);
  return {p.x + (q.x - p.x) * f, p.y + (q.y - p.y) * f};
}

// One triangle's piece of one level's line: from the crossing on edge `from` to the one on
// edge `to` (edge keys), with their points.
struct Segment {
  int64_t k = 0;  // the level is base + k * interval
  uint64_t from = 0, to = 0;
  Point2 p, q;
};

// The segment of triangle t at `level`, if the level crosses it. Edge i runs from v[i] to v[i+1]
// (counter-clockwise); going round, the edge from below to above has the low ground on its
// start side, so a segment from that edge to the one from above to below has the low ground on
// its left and the high ground on its right.
bool SegmentAt(const Tin& tin, const TinTriangle& t, double level, Segment* out) {
  int up = -1, down = -1;
  for (int i = 0; i < 3; ++i) {
    const bool a_above = tin.vertices[t.v[i]].z >= level;
    const bool b_above = tin.vertices[t.v[(i + 1) % 3]].z >= level;
    if (!a_above && b_above) up = i;
    if (a_above && !b_above) down = i;
  }
  if (up < 0 || down < 0) return false;
  const auto a = [&](int i) { return t.v[static_cast<size_t>(i)]; };
  const auto b = [&](int i) { return t.v[static_cast<size_t>((i + 1) % 3)]; };
  out->from = EdgeKey(a(up), b(up));
  out->to = EdgeKey(a(down), b(down));
  out->p = Crossing(tin, a(up), b(up), level);
  out->q = Crossing(tin, a(down), b(down), level);
  return true;
}

void Append(std::vector<Point2>& line, const Point2& p) {
  if (line.empty() || line.back().x != p.x || line.back().y != p.y) line.push_back(p);
}

// Joins one level's segments (each crossing starts at most one and ends at most one) into
// polylines: open ones from the crossings no segment ends at, in key order, then the rings.
void JoinLevel(const std::vector<Segment>& segments, double level, std::vector<ContourLine>& out) {
  std::unordered_map<uint64_t, const Segment*> starting;
  std::unordered_map<uint64_t, bool> ends;
  starting.reserve(segments.size());
  for (const Segment& s : segments) starting[s.from] = &s, ends[s.to] = true;
  const auto keep = [&](ContourLine line) {
    if (line.closed && line.points.size() > 1 && line.points.back().x == line.points[0].x &&
        line.points.back().y == line.points[0].y)
      line.points.pop_back();
    if (line.points.size() >= (line.closed ? 3u : 2u)) out.push_back(std::move(line));
  };
  const auto walk = [&](uint64_t start) {
    ContourLine line;
    line.level = level;
    for (uint64_t at = start;;) {
      auto it = starting.find(at);
      if (it == starting.end()) break;
      const Segment& s = *it->second;
      starting.erase(it);
      Append(line.points, s.p);
      if (s.to == start) {
        line.closed = true;
        break;
      }
      if (!starting.count(s.to)) Append(line.points, s.q);
      at = s.to;
    }
    keep(std::move(line));
  };
  for (const Segment& s : segments) {
    if (!ends.count(s.from)) walk(s.from);
  }
  for (const Segment& s : segments) {
    if (starting.count(s.from)) walk(s.from);
  }
}

}  // namespace

Result<std::vector<ContourLine>> TraceContours(const Tin& tin, const ContourOptions& options) {
  if (!std::isfinite(options.interval) || !(options.interval > 0))
    return Status::InvalidArgument("contour interval must be a positive number, got " +
                                   Text(options.interval));
  if (!std::isfinite(options.base))
    return Status::InvalidArgument("contour base must be a finite number, got " +
                                   Text(options.base));
  std::vector<uint32_t> triangles;
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (uint32_t i = 0; i < tin.triangles.size(); ++i) {
    const TinTriangle& t = tin.triangles[i];
    if (options.visible_only && !t.visible) continue;
    triangles.push_back(i);
    for (uint32_t v : t.v)
      lo = std::min(lo, tin.vertices[v].z), hi = std::max(hi, tin.vertices[v].z);
  }
  std::vector<ContourLine> out;
  if (triangles.empty()) return Status::InvalidArgument("the surface has no visible triangle");
  const double first = std::ceil((lo - options.base) / options.interval);
  const double last = std::floor((hi - options.base) / options.interval);
  if (last - first + 1 > kMaxLevels)
    return Status::InvalidArgument("contour interval " + Text(options.interval) + " gives " +
                                   Text(last - first + 1) + " levels between z " + Text(lo) +
                                   " and " + Text(hi) + " (at most " + std::to_string(kMaxLevels) +
                                   ")");
  // Each triangle adds its segment at each level between its lowest and highest corner, so the
  // work is the size of the answer, not levels times triangles. Sorted by (level, start edge),
  // the output does not depend on hash order.
  std::vector<Segment> segments;
  for (uint32_t index : triangles) {
    const TinTriangle& t = tin.triangles[index];
    double t_lo = tin.vertices[t.v[0]].z, t_hi = t_lo;
    for (uint32_t v : t.v)
      t_lo = std::min(t_lo, tin.vertices[v].z), t_hi = std::max(t_hi, tin.vertices[v].z);
    // One level of margin either side; SegmentAt decides exactly.
    const double k_lo = std::max(first, std::floor((t_lo - options.base) / options.interval));
    const double k_hi = std::min(last, std::floor((t_hi - options.base) / options.interval) + 1);
    for (double k = k_lo; k <= k_hi; k += 1) {
      Segment s;
      s.k = static_cast<int64_t>(k);
      if (SegmentAt(tin, t, options.base + k * options.interval, &s)) segments.push_back(s);
    }
  }
  std::sort(segments.begin(), segments.end(), [](const Segment& a, const Segment& b) {
    return a.k != b.k ? a.k < b.k : a.from < b.from;
  });
  for (size_t begin = 0; begin < segments.size();) {
    size_t end = begin;
    while (end < segments.size() && segments[end].k == segments[begin].k) ++end;
    const std::vector<Segment> level(segments.begin() + static_cast<std::ptrdiff_t>(begin),
                                     segments.begin() + static_cast<std::ptrdiff_t>(end));
    JoinLevel(level, options.base + static_cast<double>(segments[begin].k) * options.interval, out);
    begin = end;
  }
  if (out.empty())
    return Status::InvalidArgument("no contour line at interval " + Text(options.interval) +
                                   " from base " + Text(options.base) + ": the surface spans z " +
                                   Text(lo) + " to " + Text(hi));
  return out;
}

}  // namespace tinbase
