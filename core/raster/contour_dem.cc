#include "core/raster/contour_dem.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <optional>
#include <sstream>
#include <unordered_set>

#include "core/geometry/cdt.h"
#include "core/tin/tin_raster.h"

namespace tinbase {
namespace {

struct Segment {
  uint32_t line = 0;
  Point2 a, b;
};

std::string At(const Point2& p) {
  std::ostringstream out;
  out.precision(12);
  out << "(" << p.x << ", " << p.y << ")";
  return out.str();
}

std::string Describe(const ContourLine& line) {
  std::ostringstream out;
  out.precision(12);
  out << line.label << " (level " << line.level << ")";
  return out.str();
}

// p on the closed segment ab, given that a, b, p are collinear.
bool WithinCollinear(const Point2& a, const Point2& b, const Point2& p) {
  return p.x >= std::min(a.x, b.x) && p.x <= std::max(a.x, b.x) && p.y >= std::min(a.y, b.y) &&
         p.y <= std::max(a.y, b.y);
}

// Where s and t meet in a way the rules forbid: a proper crossing always; for different levels,
// any shared point. Orientation signs are exact, so "proper crossing" and "touching" are decided
// exactly; only the reported crossing point is rounded.
std::optional<Point2> ForbiddenContact(const Segment& s, const Segment& t, bool same_level) {
  const int o1 = Orientation(s.a, s.b, t.a), o2 = Orientation(s.a, s.b, t.b);
  const int o3 = Orientation(t.a, t.b, s.a), o4 = Orientation(t.a, t.b, s.b);
  if (o1 * o2 < 0 && o3 * o4 < 0) {
    const double dx = s.b.x - s.a.x, dy = s.b.y - s.a.y;
    const double ex = t.b.x - t.a.x, ey = t.b.y - t.a.y;
    const double u = ((t.a.x - s.a.x) * ey - (t.a.y - s.a.y) * ex) / (dx * ey - dy * ex);
    return Point2{s.a.x + u * dx, s.a.y + u * dy};
  }
  if (same_level) return std::nullopt;
  if (o1 == 0 && WithinCollinear(s.a, s.b, t.a)) return t.a;
  if (o2 == 0 && WithinCollinear(s.a, s.b, t.b)) return t.b;
  if (o3 == 0 && WithinCollinear(t.a, t.b, s.a)) return s.a;
  if (o4 == 0 && WithinCollinear(t.a, t.b, s.b)) return s.b;
  return std::nullopt;
}

uint64_t EdgeKey(uint32_t a, uint32_t b) {
  return (uint64_t{std::min(a, b)} << 32) | std::max(a, b);
}

double Distance(const Point2& p, const TinVertex& v) { return std::hypot(p.x - v.x, p.y - v.y); }

// One Steiner point per flat triangle (see the header for the rule), at most one per edge.
class SteinerPlanner {
 public:
  explicit SteinerPlanner(const Tin& tin) : tin_(tin), stamp_(tin.triangles.size(), 0) {
    for (const auto& [a, b] : tin.constraints) constrained_.insert(EdgeKey(a, b));
  }

  bool IsFlat(const TinTriangle& t) const {
    const double z = tin_.vertices[t.v[0]].z;
    return tin_.vertices[t.v[1]].z == z && tin_.vertices[t.v[2]].z == z;
  }

  // Appends the Steiner point for flat triangle `t`, unless its edge already has one or no other
  // level can be reached from it.
  void Plan(size_t t, std::vector<TinVertex>* out) {
    const TinTriangle& tri = tin_.triangles[t];
    const double level = tin_.vertices[tri.v[0]].z;
    int longest = -1;
    double longest_length = 0;
    for (int i = 0; i < 3; ++i) {
      const uint32_t a = tri.v[(i + 1) % 3], b = tri.v[(i + 2) % 3];
      if (constrained_.count(EdgeKey(a, b))) continue;
      const double length = std::hypot(tin_.vertices[a].x - tin_.vertices[b].x,
                                       tin_.vertices[a].y - tin_.vertices[b].y);
      if (length > longest_length) {
        longest = i;
        longest_length = length;
      }
    }
    Point2 m;
    double d1;
    if (longest >= 0) {
      const uint32_t a = tri.v[(longest + 1) % 3], b = tri.v[(longest + 2) % 3];
      if (!planned_edges_.insert(EdgeKey(a, b)).second) return;
      m = {(tin_.vertices[a].x + tin_.vertices[b].x) / 2,
           (tin_.vertices[a].y + tin_.vertices[b].y) / 2};
      d1 = longest_length / 2;
    } else {
      m = {0, 0};
      for (uint32_t v : tri.v) {
        m.x += tin_.vertices[v].x / 3;
        m.y += tin_.vertices[v].y / 3;
      }
      d1 = std::numeric_limits<double>::infinity();
      for (uint32_t v : tri.v) d1 = std::min(d1, Distance(m, tin_.vertices[v]));
    }
    const std::optional<double> z = SteinerZ(t, level, m, d1);
    if (z) out->push_back(TinVertex{m.x, m.y, *z, VertexKind::kSteiner});
  }

 private:
  // Walks the flat region around `start` without crossing contours (at most kMaxWalk
  // triangles: a huge flat region is then repaired over several rounds from its edges).
  std::optional<double> SteinerZ(size_t start, double level, const Point2& m, double d1) {
    constexpr size_t kMaxWalk = 4096;
    ++current_;
    std::deque<size_t> queue{start};
    std::vector<size_t> flat_region;
    stamp_[start] = current_;
    const TinVertex* nearest = nullptr;
    double nearest_distance = std::numeric_limits<double>::infinity();
    const auto consider = [&](uint32_t v) {
      const TinVertex& w = tin_.vertices[v];
      const double d = Distance(m, w);
      if (w.z != level && d < nearest_distance) {
        nearest = &w;
        nearest_distance = d;
      }
    };
    while (!queue.empty() && flat_region.size() < kMaxWalk) {
      const size_t u = queue.front();
      queue.pop_front();
      const TinTriangle& tri = tin_.triangles[u];
      if (!IsFlat(tri)) {
        for (uint32_t v : tri.v) consider(v);
        continue;
      }
      flat_region.push_back(u);
      for (int i = 0; i < 3; ++i) {
        const int32_t n = tri.n[i];
        if (n == kNoNeighbour || stamp_[static_cast<size_t>(n)] == current_) continue;
        if (constrained_.count(EdgeKey(tri.v[(i + 1) % 3], tri.v[(i + 2) % 3]))) continue;
        stamp_[static_cast<size_t>(n)] = current_;
        queue.push_back(static_cast<size_t>(n));
      }
    }
    if (nearest != nullptr) return level + (nearest->z - level) * d1 / (d1 + nearest_distance);
    // Walk cut short: the region is not known to be closed off; later rounds reach it from its
    // repaired edges.
    if (!queue.empty()) return std::nullopt;
    // Closed off by contour `level` alone: mirror the level across that contour.
    for (size_t u : flat_region) {
      const TinTriangle& tri = tin_.triangles[u];
      for (int i = 0; i < 3; ++i) {
        if (tri.n[i] != kNoNeighbour) {
          for (uint32_t v : tin_.triangles[static_cast<size_t>(tri.n[i])].v) consider(v);
        }
      }
    }
    if (nearest != nullptr) return level + (level - nearest->z) / 2;
    return std::nullopt;
  }

  const Tin& tin_;
  std::unordered_set<uint64_t> constrained_;
  std::unordered_set<uint64_t> planned_edges_;
  std::vector<uint32_t> stamp_;
  uint32_t current_ = 0;
};

Status ValidateLines(const std::vector<ContourLine>& lines) {
  if (lines.empty()) return Status::InvalidArgument("no contour lines");
  for (const ContourLine& line : lines) {
    if (line.points.size() < 2)
      return Status::InvalidArgument(line.label + ": a contour needs at least 2 points");
    if (!std::isfinite(line.level))
      return Status::InvalidArgument(line.label + ": the level is not a finite number");
    for (size_t k = 0; k < line.points.size(); ++k) {
      if (!std::isfinite(line.points[k].x) || !std::isfinite(line.points[k].y))
        return Status::InvalidArgument(line.label + ", vertex " + std::to_string(k) +
                                       ": coordinate is not finite");
    }
  }
  return Status::Ok();
}

}  // namespace

Status CheckContoursDoNotCross(const std::vector<ContourLine>& lines) {
  std::vector<Segment> segments;
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  for (size_t l = 0; l < lines.size(); ++l) {
    const auto& p = lines[l].points;
    for (size_t k = 0; k + 1 < p.size(); ++k) {
      if (p[k].x == p[k + 1].x && p[k].y == p[k + 1].y) continue;
      segments.push_back({static_cast<uint32_t>(l), p[k], p[k + 1]});
    }
    for (const Point2& q : p) {
      min_x = std::min(min_x, q.x), max_x = std::max(max_x, q.x);
      min_y = std::min(min_y, q.y), max_y = std::max(max_y, q.y);
    }
  }
  if (segments.empty()) return Status::Ok();
  // Uniform buckets, about one segment per bucket along each axis: contour segments are short
  // and evenly spread, so each bucket holds few and the pairs tested stay near linear.
  const int64_t per_axis = std::clamp<int64_t>(
      static_cast<int64_t>(std::sqrt(static_cast<double>(segments.size()))), 1, 2048);
  const double size_x = std::max(max_x - min_x, 1e-300) / static_cast<double>(per_axis);
  const double size_y = std::max(max_y - min_y, 1e-300) / static_cast<double>(per_axis);
  const auto bucket_x = [&](double x) {
    return std::clamp<int64_t>(static_cast<int64_t>((x - min_x) / size_x), 0, per_axis - 1);
  };
  const auto bucket_y = [&](double y) {
    return std::clamp<int64_t>(static_cast<int64_t>((y - min_y) / size_y), 0, per_axis - 1);
  };
  std::vector<std::vector<uint32_t>> buckets(static_cast<size_t>(per_axis * per_axis));
  for (size_t s = 0; s < segments.size(); ++s) {
    const Segment& g = segments[s];
    for (int64_t by = bucket_y(std::min(g.a.y, g.b.y)); by <= bucket_y(std::max(g.a.y, g.b.y));
         ++by) {
      for (int64_t bx = bucket_x(std::min(g.a.x, g.b.x)); bx <= bucket_x(std::max(g.a.x, g.b.x));
           ++bx) {
        buckets[static_cast<size_t>(by * per_axis + bx)].push_back(static_cast<uint32_t>(s));
      }
    }
  }
  for (const auto& bucket : buckets) {
    for (size_t i = 0; i < bucket.size(); ++i) {
      for (size_t j = i + 1; j < bucket.size(); ++j) {
        const Segment& s = segments[bucket[i]];
        const Segment& t = segments[bucket[j]];
        const ContourLine& ls = lines[s.line];
        const ContourLine& lt = lines[t.line];
        const auto contact = ForbiddenContact(s, t, ls.level == lt.level);
        if (!contact) continue;
        if (s.line == t.line)
          return Status::InvalidArgument(Describe(ls) + " crosses itself at " + At(*contact));
        const bool cross =
            ls.level == lt.level || (Orientation(s.a, s.b, t.a) * Orientation(s.a, s.b, t.b) < 0 &&
                                     Orientation(t.a, t.b, s.a) * Orientation(t.a, t.b, s.b) < 0);
        return Status::InvalidArgument(Describe(ls) + " and " + Describe(lt) +
                                       (cross ? " cross at " : " touch at ") + At(*contact));
      }
    }
  }
  return Status::Ok();
}

Result<Tin> BuildContourTin(const std::vector<ContourLine>& lines, ContourDemReport* report) {
  TB_RETURN_IF_ERROR(ValidateLines(lines));
  TB_RETURN_IF_ERROR(CheckContoursDoNotCross(lines));
  ContourDemReport local;
  ContourDemReport& rep = report != nullptr ? *report : local;
  rep = ContourDemReport{};
  rep.lines = static_cast<int64_t>(lines.size());

  std::vector<TinVertex> points;
  for (const ContourLine& line : lines) {
    for (const Point2& p : line.points) points.push_back({p.x, p.y, line.level, VertexKind::kUser});
  }
  Cdt cdt;
  const std::vector<uint32_t> index = cdt.InsertVertices(points);
  rep.contour_vertices = static_cast<int64_t>(cdt.vertices().size());
  if (cdt.FaceCount() == 0)
    return Status::InvalidArgument(
        "the contour vertices all lie on one line: nothing to triangulate");
  size_t at = 0;
  for (const ContourLine& line : lines) {
    for (size_t k = 0; k + 1 < line.points.size(); ++k) {
      if (index[at + k] != index[at + k + 1])
        cdt.InsertConstraint(index[at + k], index[at + k + 1]);
    }
    at += line.points.size();
  }

  // Contours neither cross nor touch across levels (checked above), so CGAL constructs no vertex.
  const ElevationFn no_constructed_vertices = [](double, double) {
    return std::numeric_limits<double>::quiet_NaN();
  };
  for (;;) {
    Tin tin = cdt.ToTin(no_constructed_vertices);
    for (const TinVertex& v : tin.vertices) {
      if (std::isnan(v.z))
        return Status::InvalidArgument("contours meet at " + At({v.x, v.y}) +
                                       " in a way the triangulation cannot keep");
    }
    SteinerPlanner planner(tin);
    std::vector<size_t> flat;
    for (size_t t = 0; t < tin.triangles.size(); ++t) {
      if (planner.IsFlat(tin.triangles[t])) flat.push_back(t);
    }
    if (rep.rounds == 0) rep.flat_triangles_found = static_cast<int64_t>(flat.size());
    std::vector<TinVertex> steiner;
    if (!flat.empty() && rep.rounds < kMaxSteinerRounds) {
      for (size_t t : flat) planner.Plan(t, &steiner);
    }
    if (steiner.empty()) {
      rep.flat_triangles_left = static_cast<int64_t>(flat.size());
      rep.triangles = static_cast<int64_t>(tin.triangles.size());
      return tin;
    }
    const size_t before = cdt.vertices().size();
    cdt.InsertVertices(steiner);
    rep.steiner_points += static_cast<int64_t>(cdt.vertices().size() - before);
    ++rep.rounds;
  }
}

GridGeometry SnappedGridGeometry(double min_x, double min_y, double max_x, double max_y,
                                 double cell) {
  GridGeometry g;
  g.origin_x = std::floor(min_x / cell) * cell;
  g.origin_y = std::ceil(max_y / cell) * cell;
  g.cell_x = cell;
  g.cell_y = -cell;
  g.width =
      std::max<int64_t>(1, std::llround((std::ceil(max_x / cell) * cell - g.origin_x) / cell));
  g.height =
      std::max<int64_t>(1, std::llround((g.origin_y - std::floor(min_y / cell) * cell) / cell));
  return g;
}

Result<Grid> DemFromContours(const std::vector<ContourLine>& lines, double cell,
                             ContourDemReport* report) {
  if (!(cell > 0) || !std::isfinite(cell))
    return Status::InvalidArgument("cell size must be a positive number");
  TB_RETURN_IF_ERROR(ValidateLines(lines));
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  for (const ContourLine& line : lines) {
    for (const Point2& p : line.points) {
      min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
      min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
    }
  }
  const double cells =
      std::ceil((max_x - min_x) / cell + 2) * std::ceil((max_y - min_y) / cell + 2);
  if (cells > static_cast<double>(int64_t{1} << 31)) {
    std::ostringstream msg;
    msg << "cell size " << cell << " would make " << cells << " cells (at most 2^31)";
    return Status::InvalidArgument(msg.str());
  }
  TB_ASSIGN_OR_RETURN(Tin tin, BuildContourTin(lines, report));
  Grid grid;
  grid.geometry = SnappedGridGeometry(min_x, min_y, max_x, max_y, cell);
  grid.cells = RasteriseTin(tin, grid.geometry);
  return grid;
}

}  // namespace tinbase
