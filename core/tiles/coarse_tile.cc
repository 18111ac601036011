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

// What a coarse tile is made from, in its own tile space: x = u, y = v (0..kQuantizedMax, not
// necessarily whole numbers), z in metres; a normal per vertex (or none); and the vertices on
// each of the tile's edges, sorted along the edge.
struct TileSource {
  Tin tin;
  std::vector<Ecef> normals;
  std::array<std::vector<uint32_t>, 4> edges;  // west, east, south, north
};

Ecef DecodedNormal(const QuantizedMesh& mesh, uint32_t v) {
  Ecef n{};
  if (mesh.normals) OctDecodeNormal(&(*mesh.normals)[2 * v], &n[0], &n[1], &n[2]);
  return n;
}

// The four children of a tile (index dy * 2 + dx, dy = 0 the southern pair), mapped into the
// parent's tile space: a child's u runs over half the parent's, from dx * kQuantizedMax / 2.
// Points on the parent's edges come from the children's edge lists, so the tile across that edge,
// whose children share those edges with these, finds the same ones.
TileSource FromChildren(const std::array<const QuantizedMesh*, 4>& children,
                        const CoarseTileOptions& options) {
  TileSource out;
  const double span = options.max_height - options.min_height;
  const double half = kQuantizedMax / 2.0;
  std::array<std::vector<std::pair<double, uint32_t>>, 4> edge_points;  // (along, vertex)
  for (int c = 0; c < 4; ++c) {
    const QuantizedMesh* child = children[c];
    if (child == nullptr) continue;
    const int dx = c % 2;
    const int dy = c / 2;
    const auto base = static_cast<uint32_t>(out.tin.vertices.size());
    for (size_t i = 0; i < child->vertex_count(); ++i) {
      out.tin.vertices.push_back(
          {child->u[i] / 2.0 + dx * half, child->v[i] / 2.0 + dy * half,
           options.min_height + child->height[i] / double{kQuantizedMax} * span, VertexKind::kDem});
      if (child->normals) out.normals.push_back(DecodedNormal(*child, static_cast<uint32_t>(i)));
    }
    for (size_t t = 0; t + 2 < child->triangles.size(); t += 3) {
      TinTriangle tri;
      tri.v = {base + child->triangles[t], base + child->triangles[t + 1],
               base + child->triangles[t + 2]};
      out.tin.triangles.push_back(tri);
    }
    const auto add_edge = [&](int edge, const std::vector<uint32_t>& list, bool along_x) {
      for (uint32_t v : list) {
        const TinVertex& p = out.tin.vertices[base + v];
        edge_points[edge].emplace_back(along_x ? p.x : p.y, base + v);
      }
    };
    if (dx == 0) add_edge(0, child->west, false);
    if (dx == 1) add_edge(1, child->east, false);
    if (dy == 0) add_edge(2, child->south, true);
    if (dy == 1) add_edge(3, child->north, true);
  }
  // Sorted along the edge; where two children meet, the point both list once.
  for (int e = 0; e < 4; ++e) {
    auto& points = edge_points[e];
    std::sort(points.begin(), points.end());
    double last = -1;
    for (const auto& [along, v] : points) {
      if (along == last) continue;
      out.edges[e].push_back(v);
      last = along;
    }
  }
  return out;
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

// The source's normals as three rasters (one per ECEF component), for refined vertices.
std::array<std::vector<float>, 3> NormalRasters(const TileSource& source, const GridGeometry& g) {
  std::array<std::vector<float>, 3> out;
  if (source.normals.empty()) return out;
  for (int k = 0; k < 3; ++k) {
    Tin component = source.tin;
    for (size_t v = 0; v < component.vertices.size(); ++v)
      component.vertices[v].z = source.normals[v][k];
    out[k] = RasteriseTin(component, g);
  }
  return out;
}

}  // namespace

std::optional<QuantizedMesh> MergeChildren(const std::array<const QuantizedMesh*, 4>& children,
                                           const TileKey& key, const CoarseTileOptions& options) {
  if (std::all_of(children.begin(), children.end(), [](auto* c) { return c == nullptr; }))
    return std::nullopt;
  const TileSource source = FromChildren(children, options);
  const Tin& tin = source.tin;
  const bool normals = !source.normals.empty();
  const GridGeometry g = TileRaster(options.raster);
  Grid grid;
  grid.geometry = g;
  grid.cells = RasteriseTin(tin, g);

  // Seeds: the thinned edge points, and the four corners (at the bottom of the height range
  // where the surface does not reach them, the same in every tile that shares the corner).
  std::set<uint32_t> kept;
  DouglasPeucker(tin, source.edges[0], false, options.error, &kept);
  DouglasPeucker(tin, source.edges[1], false, options.error, &kept);
  DouglasPeucker(tin, source.edges[2], true, options.error, &kept);
  DouglasPeucker(tin, source.edges[3], true, options.error, &kept);
  std::vector<TinVertex> seeds;
  std::vector<Ecef> seed_normals;
  for (uint32_t v : kept) {
    seeds.push_back(tin.vertices[v]);
    seed_normals.push_back(normals ? source.normals[v] : Ecef{});
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

  const auto normal_rasters = NormalRasters(source, g);
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
  TileMeshBuilder builder(rect, options.min_height, options.max_height, normals);
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

std::vector<uint8_t> MergeWaterMasks(const std::array<const QuantizedMesh*, 4>& children) {
  constexpr int kSize = 256;
  constexpr int kHalf = kSize / 2;
  const auto child_cell = [&](const QuantizedMesh* child, int col, int row) -> uint8_t {
    if (child == nullptr || !child->water_mask) return 0;
    const auto& m = *child->water_mask;
    return m.size() == 1 ? m[0] : m[static_cast<size_t>(row) * kSize + col];
  };
  std::vector<uint8_t> mask(kSize * kSize, 0);
  for (int row = 0; row < kSize; ++row)
    for (int col = 0; col < kSize; ++col) {
      // Rows run north to south: the upper half of the parent is its northern children (dy 1).
      const int dx = col / kHalf;
      const int dy = row < kHalf ? 1 : 0;
      const QuantizedMesh* child = children[dy * 2 + dx];
      const int c0 = 2 * (col % kHalf);
      const int r0 = 2 * (row % kHalf);
      uint8_t water = 0;
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) water = std::max(water, child_cell(child, c0 + a, r0 + b));
      mask[static_cast<size_t>(row) * kSize + col] = water;
    }
  if (std::all_of(mask.begin(), mask.end(), [&](uint8_t m) { return m == mask[0]; }))
    return {mask[0]};
  return mask;
}

}  // namespace tinbase
