#include "core/geometry/polygon_locator.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tinbase {

PolygonLocator::PolygonLocator(const std::vector<Polygon>& polygons) {
  min_x_ = min_y_ = std::numeric_limits<double>::infinity();
  max_x_ = max_y_ = -std::numeric_limits<double>::infinity();
  for (uint32_t k = 0; k < polygons.size(); ++k) {
    const auto add_ring = [&](const Ring& ring) {
      for (size_t i = 0; i < ring.size(); ++i) {
        const Point2& a = ring[i];
        edges_.push_back({a, ring[(i + 1) % ring.size()], k});
        min_x_ = std::min(min_x_, a.x);
        max_x_ = std::max(max_x_, a.x);
        min_y_ = std::min(min_y_, a.y);
        max_y_ = std::max(max_y_, a.y);
      }
    };
    add_ring(polygons[k].shell);
    for (const Ring& hole : polygons[k].holes) add_ring(hole);
  }
  if (edges_.empty()) return;
  // About one edge per band: a query then tests the few edges near its own height.
  const int64_t bands = std::clamp<int64_t>(static_cast<int64_t>(edges_.size()), 1, 1 << 20);
  band_height_ = (max_y_ - min_y_) / static_cast<double>(bands);
  if (!(band_height_ > 0)) band_height_ = 1;
  // Counting sort of (band, edge) pairs into CSR form; BandOf needs band_begin_'s size.
  band_begin_.assign(bands + 1, 0);
  for (const Edge& e : edges_) {
    const int64_t lo = BandOf(std::min(e.a.y, e.b.y)), hi = BandOf(std::max(e.a.y, e.b.y));
    for (int64_t b = lo; b <= hi; ++b) ++band_begin_[b + 1];
  }
  for (int64_t b = 0; b < bands; ++b) band_begin_[b + 1] += band_begin_[b];
  band_edges_.resize(band_begin_.back());
  std::vector<uint32_t> fill(band_begin_.begin(), band_begin_.end() - 1);
  for (uint32_t e = 0; e < edges_.size(); ++e) {
    const int64_t lo = BandOf(std::min(edges_[e].a.y, edges_[e].b.y));
    const int64_t hi = BandOf(std::max(edges_[e].a.y, edges_[e].b.y));
    for (int64_t b = lo; b <= hi; ++b) band_edges_[fill[b]++] = e;
  }
}

int64_t PolygonLocator::BandOf(double y) const {
  const int64_t bands = static_cast<int64_t>(band_begin_.size()) - 1;
  const double band = std::floor((y - min_y_) / band_height_);
  return std::clamp<int64_t>(static_cast<int64_t>(std::clamp(band, -1.0, double(bands))), 0,
                             bands - 1);
}

PointInPolygon PolygonLocator::Locate(const Point2& p) const {
  if (edges_.empty() || p.x < min_x_ || p.x > max_x_ || p.y < min_y_ || p.y > max_y_)
    return PointInPolygon::kOutside;
  // Every edge whose y-range holds p.y is listed in p's band (edges are added to each band
  // their closed y-range meets, and BandOf is monotone), so the parity below is complete.
  const int64_t band = BandOf(p.y);
  bool on_boundary = false;  // on a ring of some polygon
  bool on_edge = false;      // on a ring of the current polygon: its parity means nothing then
  bool inside = false;
  uint32_t polygon = std::numeric_limits<uint32_t>::max();
  for (uint32_t i = band_begin_[band]; i < band_begin_[band + 1]; ++i) {
    const Edge& e = edges_[band_edges_[i]];
    if (e.polygon != polygon) {
      // Edges come grouped by polygon: the parity of the previous one is final.
      if (inside && !on_edge) return PointInPolygon::kInside;
      polygon = e.polygon;
      inside = on_edge = false;
    }
    switch (RayTest(e.a, e.b, p)) {
      case EdgeRay::kOnEdge:
        on_boundary = on_edge = true;
        break;
      case EdgeRay::kCross:
        inside = !inside;
        break;
      case EdgeRay::kMiss:
        break;
    }
  }
  if (inside && !on_edge) return PointInPolygon::kInside;
  return on_boundary ? PointInPolygon::kBoundary : PointInPolygon::kOutside;
}

}  // namespace tinbase
