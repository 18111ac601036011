// Level surfaces: see level_surfaces.h.
#include "core/tiles/level_surfaces.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/geometry/reproject.h"
#include "core/raster/grid.h"
#include "core/tin/greedy_builder.h"
#include "core/tin/tin_raster.h"

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

GridGeometry LevelRaster(const Tin& tin, int64_t max_cells) {
  const PlanBox b = BoxOf(tin);
  const double width = b.max_x - b.min_x;
  const double height = b.max_y - b.min_y;
  const auto cells = static_cast<double>(
      std::min<int64_t>(max_cells, 4 * static_cast<int64_t>(tin.vertices.size())));
  const double cell = std::max(std::sqrt(width * height / std::max(cells, 4.0)), 1e-9);
  // Cell centres on a lattice whose first and last centres lie on the box's edges, where the
  // surface is still defined.
  GridGeometry g;
  g.width = std::max<int64_t>(2, static_cast<int64_t>(std::ceil(width / cell)) + 1);
  g.height = std::max<int64_t>(2, static_cast<int64_t>(std::ceil(height / cell)) + 1);
  g.cell_x = width > 0 ? width / static_cast<double>(g.width - 1) : cell;
  g.cell_y = -(height > 0 ? height / static_cast<double>(g.height - 1) : cell);
  g.origin_x = b.min_x - g.cell_x / 2;
  g.origin_y = b.max_y - g.cell_y / 2;
  return g;
}

Result<Tin> CoarserTin(const Tin& tin, const GridGeometry& raster, double tolerance) {
  if (!(tolerance > 0))
    return Status::InvalidArgument("a level's error bound must be positive, not " +
                                   std::to_string(tolerance));
  Tin visible;
  visible.vertices = tin.vertices;
  for (const TinTriangle& t : tin.triangles)
    if (t.visible) visible.triangles.push_back(t);
  Grid grid;
  grid.geometry = raster;
  grid.cells = RasteriseTin(visible, raster);
  GreedyOptions options;
  options.tolerance = tolerance;
  return BuildGreedyTin(grid, options);
}

std::pair<double, double> HeightRange(const Tin& tin, const Crs& crs) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (const TinVertex& v : tin.vertices) lo = std::min(lo, v.z), hi = std::max(hi, v.z);
  const double metres = crs.VerticalMetresPerUnit();
  return {lo * metres, hi * metres};
}

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
  const double mid_lat = (b.min_y + b.max_y) / 2 * M_PI / 180;
  const double area = (b.max_x - b.min_x) * kMetresPerDegree * std::cos(mid_lat) *
                      (b.max_y - b.min_y) * kMetresPerDegree;
  const double spacing =
      std::sqrt(std::max(area, 1.0) / std::max<double>(1, surface.tin.vertices.size()));
  for (int level = 0; level < kMaxTileLevel; ++level) {
    const double tile_metres = TileDegrees(level) * kMetresPerDegree * std::cos(mid_lat);
    if (tile_metres / spacing <= 128) return level;
  }
  return kMaxTileLevel;
}

}  // namespace tinbase
