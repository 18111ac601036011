#include "core/measure/plan_overlay.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace tinbase {

namespace {

struct Box2 {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -std::numeric_limits<double>::infinity(), max_y = max_x;
  void Add(const Point2& p) {
    min_x = std::min(min_x, p.x), min_y = std::min(min_y, p.y);
    max_x = std::max(max_x, p.x), max_y = std::max(max_y, p.y);
  }
  bool Meets(const Box2& o) const {
    return min_x <= o.max_x && o.min_x <= max_x && min_y <= o.max_y && o.min_y <= max_y;
  }
};

using Triangle2 = std::array<Point2, 3>;

// Triangles bucketed by their boxes on a uniform grid of about one cell per triangle: a query
// box visits the triangles listed in the cells it meets (each once, by a stamp per query).
class TriangleGrid {
 public:
  explicit TriangleGrid(std::vector<Triangle2> triangles) : triangles_(std::move(triangles)) {
    boxes_.reserve(triangles_.size());
    for (const Triangle2& t : triangles_) {
      Box2 box;
      for (const Point2& p : t) box.Add(p);
      boxes_.push_back(box);
      all_.Add({box.min_x, box.min_y}), all_.Add({box.max_x, box.max_y});
    }
    if (triangles_.empty()) return;
    const double w = std::max(all_.max_x - all_.min_x, 1e-300);
    const double h = std::max(all_.max_y - all_.min_y, 1e-300);
    const double cells = std::clamp(static_cast<double>(triangles_.size()), 1.0, double{1 << 22});
    cell_ = std::sqrt(w * h / cells);
    if (!(cell_ > 0)) cell_ = std::max(w, h);
    nx_ = std::clamp<int64_t>(static_cast<int64_t>(w / cell_) + 1, 1, 4096);
    ny_ = std::clamp<int64_t>(static_cast<int64_t>(h / cell_) + 1, 1, 4096);
    cell_ = std::max(w / static_cast<double>(nx_), h / static_cast<double>(ny_));
    std::vector<std::vector<uint32_t>> lists(static_cast<size_t>(nx_ * ny_));
    for (uint32_t i = 0; i < triangles_.size(); ++i) {
      Cells(boxes_[i], [&](int64_t c) { lists[static_cast<size_t>(c)].push_back(i); });
    }
    begin_.assign(lists.size() + 1, 0);
    for (size_t c = 0; c < lists.size(); ++c) {
      begin_[c + 1] = begin_[c] + static_cast<uint32_t>(lists[c].size());
      entries_.insert(entries_.end(), lists[c].begin(), lists[c].end());
    }
    seen_.assign(triangles_.size(), 0);
  }

  const Triangle2& triangle(uint32_t i) const { return triangles_[i]; }

  // Calls f(i) for each triangle whose box meets `box`.
  template <typename F>
  void Visit(const Box2& box, F&& f) {
    if (triangles_.empty() || !box.Meets(all_)) return;
    ++stamp_;
    Cells(box, [&](int64_t c) {
      for (uint32_t k = begin_[static_cast<size_t>(c)]; k < begin_[static_cast<size_t>(c) + 1];
           ++k) {
        const uint32_t i = entries_[k];
        if (seen_[i] == stamp_ || !boxes_[i].Meets(box)) continue;
        seen_[i] = stamp_;
        f(i);
      }
    });
  }

 private:
  int64_t Column(double x) const {
    return std::clamp<int64_t>(static_cast<int64_t>(std::floor((x - all_.min_x) / cell_)), 0,
                               nx_ - 1);
  }
  int64_t Row(double y) const {
    return std::clamp<int64_t>(static_cast<int64_t>(std::floor((y - all_.min_y) / cell_)), 0,
                               ny_ - 1);
  }
  template <typename F>
  void Cells(const Box2& box, F&& f) const {
    for (int64_t r = Row(box.min_y); r <= Row(box.max_y); ++r) {
      for (int64_t c = Column(box.min_x); c <= Column(box.max_x); ++c) f(r * nx_ + c);
    }
  }

  std::vector<Triangle2> triangles_;
  std::vector<Box2> boxes_;
  Box2 all_;
  double cell_ = 1;
  int64_t nx_ = 1, ny_ = 1;
  std::vector<uint32_t> begin_, entries_;
  std::vector<uint64_t> seen_;
  uint64_t stamp_ = 0;
};

Point2 At(const Tin& tin, uint32_t v) { return {tin.vertices[v].x, tin.vertices[v].y}; }

Triangle2 PlanTriangle(const Tin& tin, const TinTriangle& t) {
  return {At(tin, t.v[0]), At(tin, t.v[1]), At(tin, t.v[2])};
}

// Which side of the directed line p->q the point s lies on: > 0 to the left.
double Side(const Point2& p, const Point2& q, const Point2& s) {
  return (q.x - p.x) * (s.y - p.y) - (q.y - p.y) * (s.x - p.x);
}

// `poly` (convex, counter-clockwise) clipped to the counter-clockwise triangle `t`; both relative
// to the same origin. Fewer than 3 points when nothing is left.
void ClipToTriangle(const Triangle2& t, std::vector<Point2>& poly, std::vector<Point2>& scratch) {
  for (int e = 0; e < 3 && poly.size() >= 3; ++e) {
    const Point2& p = t[e];
    const Point2& q = t[(e + 1) % 3];
    scratch.clear();
    for (size_t i = 0; i < poly.size(); ++i) {
      const Point2& s = poly[i];
      const Point2& u = poly[(i + 1) % poly.size()];
      const double ds = Side(p, q, s);
      const double du = Side(p, q, u);
      if (ds >= 0) scratch.push_back(s);
      if ((ds > 0 && du < 0) || (ds < 0 && du > 0)) {
        const double f = ds / (ds - du);
        scratch.push_back({s.x + (u.x - s.x) * f, s.y + (u.y - s.y) * f});
      }
    }
    poly.swap(scratch);
  }
}

double DoubleArea(const std::vector<Point2>& ring) {
  double sum = 0;
  for (size_t i = 1; i + 1 < ring.size(); ++i) {
    sum += (ring[i].x - ring[0].x) * (ring[i + 1].y - ring[0].y) -
           (ring[i].y - ring[0].y) * (ring[i + 1].x - ring[0].x);
  }
  return sum;
}

Triangle2 Shifted(const Triangle2& t, const Point2& origin) {
  return {Point2{t[0].x - origin.x, t[0].y - origin.y},
          Point2{t[1].x - origin.x, t[1].y - origin.y},
          Point2{t[2].x - origin.x, t[2].y - origin.y}};
}

Box2 BoxOf(const Triangle2& t) {
  Box2 box;
  for (const Point2& p : t) box.Add(p);
  return box;
}

std::vector<Triangle2> VisibleTriangles(const Tin& tin, std::vector<int32_t>* index) {
  std::vector<Triangle2> out;
  for (size_t i = 0; i < tin.triangles.size(); ++i) {
    if (!tin.triangles[i].visible) continue;
    out.push_back(PlanTriangle(tin, tin.triangles[i]));
    index->push_back(static_cast<int32_t>(i));
  }
  return out;
}

}  // namespace

void ForEachOverlayPiece(const Tin& a, const Tin* b, const PlanRegion* region,
                         const OverlayVisitor& visit) {
  std::vector<int32_t> b_index;
  TriangleGrid b_grid(b != nullptr ? VisibleTriangles(*b, &b_index) : std::vector<Triangle2>());
  TriangleGrid r_grid(region != nullptr ? region->triangles() : std::vector<Triangle2>());
  OverlayPiece piece;
  std::vector<Point2> ab, scratch;
  // Clips `ab` against each region triangle (or none) and visits what is left.
  const auto emit = [&](const Box2& box) {
    if (region == nullptr) {
      if (DoubleArea(ab) <= 0) return;
      piece.ring = ab;
      visit(piece);
      return;
    }
    r_grid.Visit(box, [&](uint32_t r) {
      piece.ring = ab;
      ClipToTriangle(Shifted(r_grid.triangle(r), piece.origin), piece.ring, scratch);
      if (piece.ring.size() >= 3 && DoubleArea(piece.ring) > 0) visit(piece);
    });
  };
  for (uint32_t i = 0; i < a.triangles.size(); ++i) {
    if (!a.triangles[i].visible) continue;
    const Triangle2 t = PlanTriangle(a, a.triangles[i]);
    const Box2 box = BoxOf(t);
    piece.origin = t[0];
    piece.a = i;
    const Triangle2 local = Shifted(t, t[0]);
    if (b == nullptr) {
      piece.b = -1;
      ab.assign(local.begin(), local.end());
      emit(box);
      continue;
    }
    b_grid.Visit(box, [&](uint32_t k) {
      piece.b = b_index[k];
      ab.assign(local.begin(), local.end());
      ClipToTriangle(Shifted(b_grid.triangle(k), t[0]), ab, scratch);
      if (ab.size() >= 3) emit(box);
    });
  }
}

double PlaneZ(const Tin& tin, uint32_t t, const Point2& origin, const Point2& r) {
  const auto& v = tin.triangles[t].v;
  const TinVertex& p0 = tin.vertices[v[0]];
  const TinVertex& p1 = tin.vertices[v[1]];
  const TinVertex& p2 = tin.vertices[v[2]];
  const double ux = p1.x - p0.x, uy = p1.y - p0.y, uz = p1.z - p0.z;
  const double wx = p2.x - p0.x, wy = p2.y - p0.y, wz = p2.z - p0.z;
  const double det = ux * wy - uy * wx;
  const double px = (origin.x - p0.x) + r.x;
  const double py = (origin.y - p0.y) + r.y;
  // Solve p = s u + t w for the plan offset, then z = z0 + s uz + t wz.
  const double s = (px * wy - py * wx) / det;
  const double q = (ux * py - uy * px) / det;
  return p0.z + s * uz + q * wz;
}

}  // namespace tinbase
