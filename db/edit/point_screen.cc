#include "db/edit/point_screen.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <unordered_map>
#include <utility>

#include "core/geometry/polygon.h"
#include "db/mesh/mesh_edge.h"
#include "db/point_locator.h"

namespace tinbase {
namespace {

// Indices of `points` in strips of about one point's share of the box wide, alternately up and
// down: consecutive points are near each other, so each locator walk is short.
std::vector<size_t> SpatialOrder(const std::vector<TinVertex>& points) {
  Box box;
  for (const TinVertex& p : points) box.Add(Point2{p.x, p.y});
  const double width = std::max(box.max_x - box.min_x, box.max_y - box.min_y);
  const double strips = std::max(1.0, std::floor(std::sqrt(static_cast<double>(points.size()))));
  const double strip = width > 0 ? width / strips : 1.0;
  std::vector<std::pair<int64_t, size_t>> keyed;
  keyed.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i)
    keyed.push_back({static_cast<int64_t>(std::floor((points[i].x - box.min_x) / strip)), i});
  std::vector<size_t> order(points.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const int64_t sa = keyed[a].first, sb = keyed[b].first;
    if (sa != sb) return sa < sb;
    const bool up = sa % 2 == 0;
    if (points[a].y != points[b].y)
      return up ? points[a].y < points[b].y : points[a].y > points[b].y;
    return a < b;
  });
  return order;
}

double Snap(const EditContext& ctx) { return kSnapCells * ctx.Cell(); }

}  // namespace

Result<ScreenedPoints> ScreenPoints(const EditContext& ctx, const std::vector<TinVertex>& points,
                                    const std::vector<std::string>& labels) {
  ScreenedPoints out;
  // Points onto earlier points first, in file order, so the first of a pair is the one kept.
  const double snap = Snap(ctx);
  const auto bucket = [snap](double v) { return static_cast<int64_t>(std::floor(v / snap)); };
  std::unordered_map<std::pair<int64_t, int64_t>, std::vector<size_t>, MeshEdgeHash> buckets;
  std::vector<uint8_t> duplicate(points.size(), 0);
  for (size_t i = 0; i < points.size(); ++i) {
    const TinVertex& p = points[i];
    const int64_t bx = bucket(p.x), by = bucket(p.y);
    std::optional<SnappedPoint> snapped;
    for (int64_t j = by - 1; j <= by + 1 && !snapped; ++j) {
      for (int64_t k = bx - 1; k <= bx + 1 && !snapped; ++k) {
        auto it = buckets.find({k, j});
        if (it == buckets.end()) continue;
        for (size_t e : it->second) {
          const double d = std::hypot(points[e].x - p.x, points[e].y - p.y);
          if (d > snap) continue;
          snapped = SnappedPoint{i, 0, e, d};
          break;
        }
      }
    }
    if (snapped) {
      out.snapped.push_back(*snapped);
      duplicate[i] = 1;
      continue;
    }
    buckets[{bx, by}].push_back(i);
  }
  // Then every other point located, in a spatial order, against the stored vertices.
  PointLocator locator(ctx.store, ctx.surface, &ctx.mesh);
  for (size_t i : SpatialOrder(points)) {
    if (duplicate[i]) continue;
    const TinVertex& p = points[i];
    auto located = locator.LocateTriangle(p.x, p.y);
    if (!located.ok()) {
      if (located.status().code() != StatusCode::kNotFound) return located.status();
      return Status::InvalidArgument(labels[i] + ": " + FormatPoint({p.x, p.y}) +
                                     " lies outside surface '" + ctx.surface.name + "'");
    }
    TB_ASSIGN_OR_RETURN(const TriangleRow* tri, ctx.mesh.Triangle(located->triangle));
    const TriangleRow corners = *tri;
    std::optional<SnappedPoint> snapped;
    for (int64_t v : corners.v) {
      TB_ASSIGN_OR_RETURN(Point2 q, ctx.mesh.At(v));
      const double d = std::hypot(q.x - p.x, q.y - p.y);
      if (d <= snap && (!snapped || d < snapped->distance)) snapped = SnappedPoint{i, v, 0, d};
    }
    if (snapped) {
      out.snapped.push_back(*snapped);
      continue;
    }
    out.kept.push_back(i);
    out.box.Add(Point2{p.x, p.y});
  }
  std::sort(out.snapped.begin(), out.snapped.end(),
            [](const SnappedPoint& a, const SnappedPoint& b) { return a.index < b.index; });
  return out;
}

Result<int64_t> SurveyVertexAt(const EditContext& ctx, const TinVertex& p) {
  PointLocator locator(ctx.store, ctx.surface, &ctx.mesh);
  auto located = locator.LocateTriangle(p.x, p.y);
  if (!located.ok()) {
    if (located.status().code() == StatusCode::kNotFound) return int64_t{0};
    return located.status();
  }
  TB_ASSIGN_OR_RETURN(const TriangleRow* tri, ctx.mesh.Triangle(located->triangle));
  const TriangleRow corners = *tri;
  int64_t best = 0;
  double best_d = Snap(ctx);
  for (int64_t v : corners.v) {
    TB_ASSIGN_OR_RETURN(const TinVertex* w, ctx.mesh.Vertex(v));
    const double d = std::hypot(w->x - p.x, w->y - p.y);
    if (w->kind == VertexKind::kUser && d <= best_d) best = v, best_d = d;
  }
  return best;
}

std::string DescribeSnap(const SnappedPoint& s, const std::vector<TinVertex>& points,
                         const std::vector<std::string>& labels) {
  char distance[32];
  std::snprintf(distance, sizeof distance, "%.3g", s.distance);
  const TinVertex& p = points[s.index];
  const std::string onto = s.vertex != 0 ? "vertex " + std::to_string(s.vertex) : labels[s.earlier];
  return labels[s.index] + ": " + FormatPoint({p.x, p.y}) + " snapped onto " + onto + " (" +
         distance + " away), left out";
}

}  // namespace tinbase
