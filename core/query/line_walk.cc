#include "core/query/line_walk.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>

namespace tinbase {

const char* StationKindName(StationKind kind) {
  switch (kind) {
    case StationKind::kStart:
      return "start";
    case StationKind::kEdge:
      return "edge";
    case StationKind::kVertex:
      return "vertex";
    case StationKind::kBend:
      return "bend";
    case StationKind::kEnd:
      return "end";
  }
  return "?";
}

double InterpolateZ(const WalkTriangle& t, double x, double y) {
  const double bx = t.p[1].x - t.p[0].x, by = t.p[1].y - t.p[0].y;
  const double cx = t.p[2].x - t.p[0].x, cy = t.p[2].y - t.p[0].y;
  const double px = x - t.p[0].x, py = y - t.p[0].y;
  const double det = bx * cy - by * cx;
  if (det == 0) return t.z[0];  // degenerate; CheckStore reports it
  const double l1 = (px * cy - py * cx) / det;
  const double l2 = (bx * py - by * px) / det;
  return t.z[0] + l1 * (t.z[1] - t.z[0]) + l2 * (t.z[2] - t.z[0]);
}

namespace {

// A vertex has few triangles around it; a rotation longer than this follows broken links.
constexpr int kMaxStar = 1 << 16;
// No segment of a real profile crosses this many triangles; a walk that does is cycling.
constexpr int64_t kMaxSteps = int64_t{1} << 28;

std::string Number(double v) {
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  return std::string(buf, end);
}

// Built by appending: GCC 12 warns (-Wrestrict, falsely) on "(" + std::string here.
std::string PointText(const Point2& p) {
  std::string text = "(";
  text += Number(p.x);
  text += ", ";
  text += Number(p.y);
  return text + ")";
}

bool Same(const Point2& a, const Point2& b) { return a.x == b.x && a.y == b.y; }

double Cross(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

// Whether p lies in the closed triangle.
bool Holds(const WalkTriangle& t, const Point2& p) {
  for (int i = 0; i < 3; ++i)
    if (Orientation(t.p[(i + 1) % 3], t.p[(i + 2) % 3], p) < 0) return false;
  return true;
}

// The walk along one segment S->E of the line at a time, from triangle to triangle.
class Walker {
 public:
  Walker(const WalkTriangleReader& read, LineWalk& out) : read_(read), out_(out) {}

  Status Start(int64_t triangle, const Point2& first) {
    TB_RETURN_IF_ERROR(Enter(triangle));
    out_.stations.push_back(
        {0, first.x, first.y, InterpolateZ(tri_, first.x, first.y), StationKind::kStart});
    return Status::Ok();
  }

  // Walks from s (where the last segment ended, in the current triangle) to e; `target` is e's
  // 0-based index in the line, for messages.
  Status Segment(const Point2& s, const Point2& e, size_t target, StationKind end_kind) {
    s_ = s, e_ = e, target_ = target;
    const double length = std::hypot(e.x - s.x, e.y - s.y);
    TB_RETURN_IF_ERROR(LeaveStart());
    for (int64_t steps = 0;; ++steps) {
      if (steps > kMaxSteps)
        return Status::Corruption("the walk from " + PointText(s_) + " to " + PointText(e_) +
                                  " does not end; run tinbase check");
      if (Holds(tri_, e_)) {
        Add(base_ + length, e_.x, e_.y, InterpolateZ(tri_, e_.x, e_.y), end_kind);
        base_ += length;
        return Status::Ok();
      }
      TB_RETURN_IF_ERROR(Step());
    }
  }

 private:
  Status Enter(int64_t id) {
    TB_ASSIGN_OR_RETURN(tri_, read_(id));
    current_ = id;
    return Status::Ok();
  }

  // Moves across edge i of the current triangle (opposite corner i) to its neighbour, which
  // must have that edge the other way round: broken links give an error rather than a walk
  // that never ends.
  Status EnterAcross(int i) {
    const int64_t from = current_, a = tri_.v[(i + 1) % 3], b = tri_.v[(i + 2) % 3];
    TB_RETURN_IF_ERROR(Enter(*tri_.n[i]));
    for (int j = 0; j < 3; ++j)
      if (tri_.v[(j + 1) % 3] == b && tri_.v[(j + 2) % 3] == a) return Status::Ok();
    return Status::Corruption("triangle " + std::to_string(current_) + " is linked across edge " +
                              std::to_string(a) + "-" + std::to_string(b) + " of triangle " +
                              std::to_string(from) + " but does not have it; run tinbase check");
  }

  int Side(const Point2& p) const { return Orientation(s_, e_, p); }

  Status LeavesSurface(const Point2& where) const {
    return Status::InvalidArgument("the line leaves the surface at " + PointText(where) +
                                   " on its way to point " + std::to_string(target_ + 1));
  }

  // From s_ in the current triangle, moves to a triangle the segment runs through: s_ may be on
  // a vertex, or on an edge with the segment pointing out of the triangle.
  Status LeaveStart() {
    for (int j = 0; j < 3; ++j)
      if (Same(tri_.p[j], s_)) return Pivot(j);
    for (int i = 0; i < 3; ++i) {
      const Point2& a = tri_.p[(i + 1) % 3];
      const Point2& b = tri_.p[(i + 2) % 3];
      if (Orientation(a, b, s_) != 0 || Orientation(a, b, e_) >= 0) continue;
      if (!tri_.n[i]) return LeavesSurface(s_);
      return EnterAcross(i);
    }
    return Status::Ok();
  }

  // Whether the segment, passing through corner j of `t`, goes on into `t`: the corners after
  // it are right of (or on) and left of (or on) the line, not both on it. A triangle's angle is
  // below 180 degrees, so such a wedge holds the forward direction, never the backward one.
  bool GoesInto(const WalkTriangle& t, int j) const {
    const int u = Side(t.p[(j + 1) % 3]), w = Side(t.p[(j + 2) % 3]);
    return u <= 0 && w >= 0 && !(u == 0 && w == 0);
  }

  // The segment passes through corner j of the current triangle: turns around that vertex to
  // the triangle it goes on into.
  Status Pivot(int j) {
    const int64_t vertex = tri_.v[j];
    const Point2 at = tri_.p[j];
    const int64_t first = current_;
    // Counter-clockwise around the vertex, then clockwise from the first triangle when the
    // vertex is on the boundary.
    for (int direction : {1, 2}) {
      if (direction == 2) TB_RETURN_IF_ERROR(Enter(first));
      for (int steps = 0; steps < kMaxStar; ++steps) {
        int k = -1;
        for (int i = 0; i < 3; ++i)
          if (tri_.v[i] == vertex) k = i;
        if (k < 0)
          return Status::Corruption("triangle " + std::to_string(current_) +
                                    " is linked around vertex " + std::to_string(vertex) +
                                    " but does not have it; run tinbase check");
        if (GoesInto(tri_, k)) return Status::Ok();
        const std::optional<int64_t> next = tri_.n[(k + direction) % 3];
        if (!next) break;
        if (*next == first) return LeavesSurface(at);  // all the way round: none goes on
        TB_RETURN_IF_ERROR(Enter(*next));
      }
    }
    return LeavesSurface(at);
  }

  // One step out of the current triangle, which the segment runs through and which does not
  // hold e_: across an edge, or to a vertex the segment passes through.
  Status Step() {
    for (int i = 0; i < 3; ++i) {
      const int u = (i + 1) % 3, w = (i + 2) % 3;
      const int su = Side(tri_.p[u]), sw = Side(tri_.p[w]);
      if (!(su <= 0 && sw >= 0) || (su == 0 && sw == 0)) continue;
      if (su == 0 || sw == 0) {
        const int j = su == 0 ? u : w;
        const Point2& p = tri_.p[j];
        const double dx = e_.x - s_.x, dy = e_.y - s_.y;
        const double along = ((p.x - s_.x) * dx + (p.y - s_.y) * dy) / std::hypot(dx, dy);
        Add(std::max(base_ + along, out_.stations.back().distance), p.x, p.y, tri_.z[j],
            StationKind::kVertex);
        return Pivot(j);
      }
      AddCrossing(u, w);
      if (!tri_.n[i]) return LeavesSurface({out_.stations.back().x, out_.stations.back().y});
      return EnterAcross(i);
    }
    return Status::Corruption("the line from " + PointText(s_) + " to " + PointText(e_) +
                              " runs through triangle " + std::to_string(current_) +
                              " by its links but not by its corners; run tinbase check");
  }

  // Records where the segment crosses the edge from corner u to corner w of the current
  // triangle. Both corners are strictly on opposite sides of the line, so the lines meet. The
  // rounded distance is kept from running backwards, which crossings close together could.
  void AddCrossing(int u, int w) {
    const Point2 &a = tri_.p[u], &b = tri_.p[w];
    const double dx = e_.x - s_.x, dy = e_.y - s_.y;
    const double ex = b.x - a.x, ey = b.y - a.y;
    const double denom = Cross(dx, dy, ex, ey);
    const double t = std::clamp(Cross(a.x - s_.x, a.y - s_.y, ex, ey) / denom, 0.0, 1.0);
    const double f = std::clamp(Cross(a.x - s_.x, a.y - s_.y, dx, dy) / denom, 0.0, 1.0);
    const double distance = std::max(base_ + t * std::hypot(dx, dy), out_.stations.back().distance);
    Add(distance, a.x + f * ex, a.y + f * ey, tri_.z[u] + f * (tri_.z[w] - tri_.z[u]),
        StationKind::kEdge);
  }

  // Closes the stretch in the current triangle at a new station.
  void Add(double distance, double x, double y, double z, StationKind kind) {
    out_.triangles.push_back(current_);
    out_.stations.push_back({distance, x, y, z, kind});
  }

  const WalkTriangleReader& read_;
  LineWalk& out_;
  WalkTriangle tri_;
  int64_t current_ = 0;
  Point2 s_, e_;
  size_t target_ = 0;
  double base_ = 0;  // the line's length before s_
};

}  // namespace

Result<LineWalk> WalkLine(const std::vector<Point2>& line, int64_t start_triangle,
                          const WalkTriangleReader& read) {
  LineWalk out;
  Walker walker(read, out);
  TB_RETURN_IF_ERROR(walker.Start(start_triangle, line.front()));
  size_t last = line.size() - 1;
  while (last > 0 && Same(line[last], line[last - 1])) --last;
  size_t from = 0;
  for (size_t k = 1; k <= last; ++k) {
    if (Same(line[k], line[from])) continue;
    TB_RETURN_IF_ERROR(
        walker.Segment(line[from], line[k], k, k == last ? StationKind::kEnd : StationKind::kBend));
    from = k;
  }
  return out;
}

}  // namespace tinbase
