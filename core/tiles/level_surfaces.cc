// Level surfaces: see level_surfaces.h.
#include "core/tiles/level_surfaces.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/geometry/reproject.h"

namespace tinbase {

namespace {

struct PlanBox {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -std::numeric_limits<double>::infinity(), max_y = max_x;
};

PlanBox BoxOf(const Tin& tin) {
  PlanBox b;
  for (const TinVertex& v : tin.vertices) {
    b.min_x = std::min(b.min_x, v.x), b.max_x = std::max(b.max_x, v.x);
    b.min_y = std::min(b.min_y, v.y), b.max_y = std::max(b.max_y, v.y);
  }
  return b;
}

constexpr double kMetresPerDegree = 111319.49;  // along the equator, WGS 84

}  // namespace

Result<GeoSurface> GeographicSurface(const Tin& tin, const Crs& crs, bool normals,
                                     double min_height, double max_height) {
  TB_ASSIGN_OR_RETURN(Crs wgs84, Crs::FromUserInput("EPSG:4326"));
  GeoSurface out;
  out.tin = tin;
  TB_RETURN_IF_ERROR(ReprojectXy(crs, wgs84, out.tin.vertices));
  ConvertHeightUnits(crs, wgs84, out.tin.vertices);
  if (normals) out.normals = VertexNormals(out.tin);
  out.min_height = min_height;
  out.max_height = max_height;
  return out;
}

int NaturalMaxZoom(const GeoSurface& surface) {
  const PlanBox b = BoxOf(surface.tin);
  return NaturalMaxZoom(b.min_x, b.min_y, b.max_x, b.max_y, surface.tin.vertices.size());
}

int NaturalMaxZoom(double west, double south, double east, double north, size_t vertices) {
  const double mid_lat = (south + north) / 2 * M_PI / 180;
  const double area =
      (east - west) * kMetresPerDegree * std::cos(mid_lat) * (north - south) * kMetresPerDegree;
  const double spacing = std::sqrt(std::max(area, 1.0) / std::max<double>(1, vertices));
  for (int level = 0; level < kMaxTileLevel; ++level) {
    const double tile_metres = TileDegrees(level) * kMetresPerDegree * std::cos(mid_lat);
    if (tile_metres / spacing <= 128) return level;
  }
  return kMaxTileLevel;
}

}  // namespace tinbase
