#include "core/measure/contour_lines.h"

#include <algorithm>
#include <cmath>
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

// The segments of one level: from -> to by crossed edge.
struct LevelSegments {
  std::unordered_map<uint64_t, uint64_t> next;  // edge where a segment starts -> where it ends
  std::unordered_map<uint64_t, uint64_t> prev;
  std::unordered_map<uint64_t, Point2> point;
};

LevelSegments Segments(const Tin& tin, const std::vector<uint32_t>& triangles, double level) {
  LevelSegments s;
  for (uint32_t index : triangles) {
    const TinTriangle& t = tin.triangles[index];
    // Edge i runs from v[i] to v[i+1] (counter-clockwise). Going round, the edge from below to
    // above has the low ground on its start side; the segment runs from that edge to the one from
    // above to below, with low ground on its left, high on its right.
    int64_t up = -1, down = -1;
    for (int i = 0; i < 3; ++i) {
      const bool a_above = tin.vertices[t.v[i]].z >= level;
      const bool b_above = tin.vertices[t.v[(i + 1) % 3]].z >= level;
      if (!a_above && b_above) up = i;
      if (a_above && !b_above) down = i;
    }
    if (up < 0 || down < 0) continue;
    const auto key = [&](int64_t i) {
      return EdgeKey(t.v[static_cast<size_t>(i)], t.v[static_cast<size_t>((i + 1) % 3)]);
    };
    const uint64_t from = key(up), to = key(down);
    for (int64_t i : {up, down}) {
      const uint64_t k = key(i);
      if (!s.point.count(k))
        s.point[k] = Crossing(tin, t.v[static_cast<size_t>(i)],
                              t.v[static_cast<size_t>((i + 1) % 3)], level);
    }
    s.next[from] = to;
    s.prev[to] = from;
  }
  return s;
}

void Append(std::vector<Point2>& line, const Point2& p) {
  if (line.empty() || line.back().x != p.x || line.back().y != p.y) line.push_back(p);
}

// Walks from `start` along next until the chain ends or comes back, erasing what it uses.
ContourLine Walk(LevelSegments& s, uint64_t start, double level) {
  ContourLine line;
  line.level = level;
  uint64_t at = start;
  Append(line.points, s.point[at]);
  while (true) {
    auto it = s.next.find(at);
    if (it == s.next.end()) break;
    const uint64_t to = it->second;
    s.next.erase(it);
    if (to == start) {
      line.closed = true;
      break;
    }
    Append(line.points, s.point[to]);
    at = to;
  }
  if (line.closed && line.points.size() > 1 && line.points.back().x == line.points.front().x &&
      line.points.back().y == line.points.front().y)
    line.points.pop_back();
  return line;
}

void TraceLevel(const Tin& tin, const std::vector<uint32_t>& triangles, double level,
                std::vector<ContourLine>& out) {
  LevelSegments s = Segments(tin, triangles, level);
  // Open lines start at a crossing no segment ends at; sorted keys keep the output stable.
  std::vector<uint64_t> starts;
  for (const auto& [from, to] : s.next) {
    if (!s.prev.count(from)) starts.push_back(from);
  }
  std::sort(starts.begin(), starts.end());
  const auto keep = [&](ContourLine line) {
    const size_t needed = line.closed ? 3 : 2;
    if (line.points.size() >= needed) out.push_back(std::move(line));
  };
  for (uint64_t start : starts) keep(Walk(s, start, level));
  std::vector<uint64_t> rest;
  for (const auto& [from, to] : s.next) rest.push_back(from);
  std::sort(rest.begin(), rest.end());
  for (uint64_t start : rest) {
    if (s.next.count(start)) keep(Walk(s, start, level));
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
  for (double k = first; k <= last; k += 1) {
    TraceLevel(tin, triangles, options.base + k * options.interval, out);
  }
  if (out.empty())
    return Status::InvalidArgument("no contour line at interval " + Text(options.interval) +
                                   " from base " + Text(options.base) + ": the surface spans z " +
                                   Text(lo) + " to " + Text(hi));
  return out;
}

}  // namespace tinbase
