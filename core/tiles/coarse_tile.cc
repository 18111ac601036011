// Coarse tile: see coarse_tile.h.
#include "core/tiles/coarse_tile.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "core/geometry/cdt.h"
#include "core/raster/grid.h"
#include "core/tiles/tile_mesh_builder.h"
#include "core/tin/tin_raster.h"
#include "core/tin/tolerance_refiner.h"

namespace tinbase {

namespace {

// The finest cut as a Tin in tile space: x = u, y = v (0..kQuantizedMax), z in metres.
Tin TileSpaceTin(const QuantizedMesh& cut, const CoarseTileOptions& options) {
  Tin tin;
  const double span = options.max_height - options.min_height;
  for (size_t i = 0; i < cut.vertex_count(); ++i)
    tin.vertices.push_back({static_cast<double>(cut.u[i]), static_cast<double>(cut.v[i]),
                            options.min_height + cut.height[i] / double{kQuantizedMax} * span,
                            VertexKind::kDem});
  for (size_t t = 0; t + 2 < cut.triangles.size(); t += 3) {
    TinTriangle tri;
    tri.v = {cut.triangles[t], cut.triangles[t + 1], cut.triangles[t + 2]};
    tin.triangles.push_back(tri);
  }
  return tin;
}

GridGeometry TileRaster(int cells) {
  GridGeometry g;
  g.width = cells;
  g.height = cells;
  g.cell_x = double{kQuantizedMax} / cells;
  g.cell_y = -double{kQuantizedMax} / cells;
  g.origin_x = 0;
  g.origin_y = kQuantizedMax;
  return g;
}

// Indices into `edge` (sorted along it) kept by Douglas-Peucker within `error` of height, the
// ends always.
void DouglasPeucker(const Tin& tin, const std::vector<uint32_t>& edge, bool along_x, double error,
                    std::set<uint32_t>* kept) {
  if (edge.empty()) return;
  kept->insert(edge.front());
  kept->insert(edge.back());
  std::vector<std::pair<size_t, size_t>> spans = {{0, edge.size() - 1}};
  while (!spans.empty()) {
    const auto [a, b] = spans.back();
    spans.pop_back();
    if (b <= a + 1) continue;
    const TinVertex& pa = tin.vertices[edge[a]];
    const TinVertex& pb = tin.vertices[edge[b]];
    const double sa = along_x ? pa.x : pa.y;
    const double sb = along_x ? pb.x : pb.y;
    size_t worst = a;
    double worst_error = error;
    for (size_t i = a + 1; i < b; ++i) {
      const TinVertex& p = tin.vertices[edge[i]];
      const double s = along_x ? p.x : p.y;
      const double line = pa.z + (pb.z - pa.z) * (s - sa) / (sb - sa);
      const double e = std::abs(p.z - line);
      if (e > worst_error) worst = i, worst_error = e;
    }
    if (worst == a) continue;
    kept->insert(edge[worst]);
    spans.emplace_back(a, worst);
    spans.emplace_back(worst, b);
  }
}

// The cell whose centre is nearest (x, y), clamped to the grid.
size_t NearestCell(const GridGeometry& g, double x, double y) {
  const auto col =
      std::clamp<int64_t>(static_cast<int64_t>(std::floor(g.ColumnAt(x) + 0.5)), 0, g.width - 1);
  const auto row =
      std::clamp<int64_t>(static_cast<int64_t>(std::floor(g.RowAt(y) + 0.5)), 0, g.height - 1);
  return static_cast<size_t>(row * g.width + col);
}

Ecef DecodedNormal(const QuantizedMesh& cut, uint32_t v) {
  Ecef n{};
  if (cut.normals) OctDecodeNormal(&(*cut.normals)[2 * v], &n[0], &n[1], &n[2]);
  return n;
}

// The finest cut's normals as three rasters (one per ECEF component), for refined vertices.
std::array<std::vector<float>, 3> NormalRasters(const QuantizedMesh& cut, const Tin& tin,
                                                const GridGeometry& g) {
  std::array<std::vector<float>, 3> out;
  if (!cut.normals) return out;
  for (int k = 0; k < 3; ++k) {
    Tin component = tin;
    for (size_t v = 0; v < component.vertices.size(); ++v)
      component.vertices[v].z = DecodedNormal(cut, static_cast<uint32_t>(v))[k];
    out[k] = RasteriseTin(component, g);
  }
  return out;
}

}  // namespace

std::optional<QuantizedMesh> SimplifyTile(const QuantizedMesh& finest_cut, const TileKey& key,
                                          const CoarseTileOptions& options) {
  const Tin tin = TileSpaceTin(finest_cut, options);
  const GridGeometry g = TileRaster(options.raster);
  Grid grid;
  grid.geometry = g;
  grid.cells = RasteriseTin(tin, g);

  // Seeds: the thinned edge points, and the four corners (at the bottom of the height range
  // where the surface does not reach them, the same in every tile that shares the corner).
  std::set<uint32_t> kept;
  DouglasPeucker(tin, finest_cut.west, false, options.error, &kept);
  DouglasPeucker(tin, finest_cut.east, false, options.error, &kept);
  DouglasPeucker(tin, finest_cut.south, true, options.error, &kept);
  DouglasPeucker(tin, finest_cut.north, true, options.error, &kept);
  std::vector<TinVertex> seeds;
  std::vector<Ecef> seed_normals;
  for (uint32_t v : kept) {
    seeds.push_back(tin.vertices[v]);
    seed_normals.push_back(DecodedNormal(finest_cut, v));
  }
  for (double x : {0.0, double{kQuantizedMax}})
    for (double y : {0.0, double{kQuantizedMax}}) {
      const bool present = std::any_of(seeds.begin(), seeds.end(),
                                       [&](const TinVertex& s) { return s.x == x && s.y == y; });
      if (!present) {
        seeds.push_back({x, y, options.min_height, VertexKind::kDem});
        seed_normals.push_back(Ecef{});
      }
    }
  Cdt cdt;
  cdt.InsertVertices(seeds);
  RefineOptions refine;
  refine.tolerance = options.error;
  RefineToTolerance(cdt, grid, refine);

  const auto normal_rasters = NormalRasters(finest_cut, tin, g);
  const auto normal_of = [&](uint32_t index, double x, double y) -> Ecef {
    if (index < seed_normals.size()) return seed_normals[index];
    if (normal_rasters[0].empty()) return Ecef{};
    const size_t cell = NearestCell(g, x, y);
    return {normal_rasters[0][cell], normal_rasters[1][cell], normal_rasters[2][cell]};
  };
  const TileRect rect = RectOf(key);
  const auto lon = [&](double u) {
    return rect.west + u / kQuantizedMax * (rect.east - rect.west);
  };
  const auto lat = [&](double v) {
    return rect.south + v / kQuantizedMax * (rect.north - rect.south);
  };
  TileMeshBuilder builder(rect, options.min_height, options.max_height,
                          finest_cut.normals.has_value());
  // Every edge point goes in, used by a triangle or not: the neighbour lists it too.
  for (size_t i = 0; i < kept.size(); ++i)
    builder.AddPoint({lon(seeds[i].x), lat(seeds[i].y), seeds[i].z, seed_normals[i]});
  for (const Cdt::FaceRef face : cdt.FiniteFaces()) {
    const auto corners = cdt.FaceCorners(face);
    const double cx = (corners[0].x + corners[1].x + corners[2].x) / 3;
    const double cy = (corners[0].y + corners[1].y + corners[2].y) / 3;
    if (std::isnan(grid.cells[NearestCell(g, cx, cy)])) continue;  // over no surface
    std::vector<TilePoint> polygon;
    for (const auto& c : corners)
      polygon.push_back({lon(c.x), lat(c.y), c.z, normal_of(c.index, c.x, c.y)});
    builder.AddPolygon(polygon);
  }
  return builder.Finish();
}

}  // namespace tinbase
