// TileMeshBuilder: see tile_mesh_builder.h.
#include "core/tiles/tile_mesh_builder.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace tinbase {

uint16_t Quantise(double value, double lo, double hi) {
  if (!(hi > lo)) return 0;
  const double q = std::round((value - lo) / (hi - lo) * kQuantizedMax);
  return static_cast<uint16_t>(std::clamp(q, 0.0, static_cast<double>(kQuantizedMax)));
}

TileMeshBuilder::TileMeshBuilder(const TileRect& rect, double min_height, double max_height,
                                 bool normals)
    : rect_(rect), min_height_(min_height), max_height_(max_height), normals_wanted_(normals) {}

void TileMeshBuilder::AddPolygon(const std::vector<TilePoint>& polygon) {
  std::vector<uint32_t> ids;
  for (const TilePoint& p : polygon) ids.push_back(VertexOf(p));
  for (size_t i = 1; i + 1 < ids.size(); ++i) AddTriangle(ids[0], ids[i], ids[i + 1]);
}

std::optional<QuantizedMesh> TileMeshBuilder::Finish() {
  if (mesh_.triangles.empty()) return std::nullopt;
  for (double h : heights_) mesh_.height.push_back(Quantise(h, min_height_, max_height_));
  for (uint32_t i = 0; i < mesh_.vertex_count(); ++i) {
    if (mesh_.u[i] == 0) mesh_.west.push_back(i);
    if (mesh_.u[i] == kQuantizedMax) mesh_.east.push_back(i);
    if (mesh_.v[i] == 0) mesh_.south.push_back(i);
    if (mesh_.v[i] == kQuantizedMax) mesh_.north.push_back(i);
  }
  if (normals_wanted_) {
    mesh_.normals.emplace(2 * mesh_.vertex_count());
    for (size_t i = 0; i < normals_.size(); ++i) {
      const Ecef& n = normals_[i];
      OctEncodeNormal(n[0], n[1], n[2], &(*mesh_.normals)[2 * i]);
    }
  }
  OrderVerticesByFirstUse(mesh_);
  DropUnused();
  SortEdges();
  mesh_.header.min_height = static_cast<float>(min_height_);
  mesh_.header.max_height = static_cast<float>(max_height_);
  std::vector<Ecef> positions;
  for (size_t i = 0; i < mesh_.vertex_count(); ++i) positions.push_back(Position(i));
  SetTileBounds(positions, mesh_.header);
  return std::move(mesh_);
}

// Points that quantise to the same u, v are one vertex: the lowest of them (and its normal),
// whatever order they come in, so that the tile across an edge, which meets the same points
// there, makes the same vertex of them.
uint32_t TileMeshBuilder::VertexOf(const TilePoint& p) {
  const uint16_t u = Quantise(p.lon, rect_.west, rect_.east);
  const uint16_t v = Quantise(p.lat, rect_.south, rect_.north);
  double length =
      std::sqrt(p.normal[0] * p.normal[0] + p.normal[1] * p.normal[1] + p.normal[2] * p.normal[2]);
  if (!(length > 0)) length = 1;
  const Ecef normal = {p.normal[0] / length, p.normal[1] / length, p.normal[2] / length};
  const auto key = std::make_pair(u, v);
  if (auto it = index_.find(key); it != index_.end()) {
    const uint32_t id = it->second;
    if (std::tie(p.h, normal) < std::tie(heights_[id], normals_[id])) {
      heights_[id] = p.h;
      normals_[id] = normal;
    }
    return id;
  }
  const auto id = static_cast<uint32_t>(mesh_.u.size());
  mesh_.u.push_back(u);
  mesh_.v.push_back(v);
  heights_.push_back(p.h);
  normals_.push_back(normal);
  index_.emplace(key, id);
  return id;
}

void TileMeshBuilder::AddTriangle(uint32_t a, uint32_t b, uint32_t c) {
  const int64_t cross = (int64_t{mesh_.u[b]} - mesh_.u[a]) * (int64_t{mesh_.v[c]} - mesh_.v[a]) -
                        (int64_t{mesh_.v[b]} - mesh_.v[a]) * (int64_t{mesh_.u[c]} - mesh_.u[a]);
  if (cross <= 0) return;  // collapsed by quantisation
  mesh_.triangles.insert(mesh_.triangles.end(), {a, b, c});
}

// Vertices no triangle uses come last after OrderVerticesByFirstUse. Those on the tile's edges
// stay (the tile across the edge may use them, and both must list the same edge vertices);
// the others go.
void TileMeshBuilder::DropUnused() {
  uint32_t used = 0;
  for (uint32_t index : mesh_.triangles) used = std::max(used, index + 1);
  const auto n = static_cast<uint32_t>(mesh_.vertex_count());
  std::vector<uint32_t> remap(n);
  uint32_t kept = used;
  for (uint32_t i = 0; i < n; ++i) {
    if (i < used) {
      remap[i] = i;
      continue;
    }
    const bool on_edge = mesh_.u[i] == 0 || mesh_.u[i] == kQuantizedMax || mesh_.v[i] == 0 ||
                         mesh_.v[i] == kQuantizedMax;
    remap[i] = on_edge ? kept++ : UINT32_MAX;
    if (!on_edge) continue;
    const uint32_t to = remap[i];
    mesh_.u[to] = mesh_.u[i];
    mesh_.v[to] = mesh_.v[i];
    mesh_.height[to] = mesh_.height[i];
    if (mesh_.normals) {
      (*mesh_.normals)[2 * to] = (*mesh_.normals)[2 * i];
      (*mesh_.normals)[2 * to + 1] = (*mesh_.normals)[2 * i + 1];
    }
  }
  mesh_.u.resize(kept);
  mesh_.v.resize(kept);
  mesh_.height.resize(kept);
  if (mesh_.normals) mesh_.normals->resize(2 * kept);
  for (auto* edge : {&mesh_.west, &mesh_.south, &mesh_.east, &mesh_.north})
    for (uint32_t& index : *edge) index = remap[index];
}

void TileMeshBuilder::SortEdges() {
  const auto by = [](const std::vector<uint16_t>& c) {
    return [&c](uint32_t a, uint32_t b) { return c[a] < c[b]; };
  };
  std::sort(mesh_.west.begin(), mesh_.west.end(), by(mesh_.v));
  std::sort(mesh_.east.begin(), mesh_.east.end(), by(mesh_.v));
  std::sort(mesh_.south.begin(), mesh_.south.end(), by(mesh_.u));
  std::sort(mesh_.north.begin(), mesh_.north.end(), by(mesh_.u));
}

Ecef TileMeshBuilder::Position(size_t i) const {
  const double lon = rect_.west + mesh_.u[i] / double{kQuantizedMax} * (rect_.east - rect_.west);
  const double lat = rect_.south + mesh_.v[i] / double{kQuantizedMax} * (rect_.north - rect_.south);
  const double h =
      min_height_ + mesh_.height[i] / double{kQuantizedMax} * (max_height_ - min_height_);
  return ToEcef(lon, lat, h);
}

}  // namespace tinbase
