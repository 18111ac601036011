// Surface selection: see surface_selection.h.
#include "db/query/surface_selection.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "core/base/number_text.h"
#include "db/mesh/mesh_tables.h"
#include "db/point_locator.h"

namespace tinbase {

namespace {

std::string Coordinates(const Box& b) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%.10g,%.10g,%.10g,%.10g", b.min_x, b.min_y, b.max_x, b.max_y);
  return buf;
}

// Whether triangle abc meets the closed box: the separating axis test over the box's two axes
// and the triangle's three edge normals (both shapes are convex, so no separating axis means
// they meet).
bool TriangleMeetsBox(const TinVertex& a, const TinVertex& b, const TinVertex& c, const Box& box) {
  if (std::max({a.x, b.x, c.x}) < box.min_x || std::min({a.x, b.x, c.x}) > box.max_x ||
      std::max({a.y, b.y, c.y}) < box.min_y || std::min({a.y, b.y, c.y}) > box.max_y)
    return false;
  const std::array<const TinVertex*, 3> v = {&a, &b, &c};
  const std::array<std::array<double, 2>, 4> corners = {{{box.min_x, box.min_y},
                                                         {box.max_x, box.min_y},
                                                         {box.max_x, box.max_y},
                                                         {box.min_x, box.max_y}}};
  for (int i = 0; i < 3; ++i) {
    const TinVertex& p = *v[i];
    const TinVertex& q = *v[(i + 1) % 3];
    const double nx = q.y - p.y;
    const double ny = p.x - q.x;
    const double tri_side = nx * (v[(i + 2) % 3]->x - p.x) + ny * (v[(i + 2) % 3]->y - p.y);
    bool all_outside = true;
    for (const auto& corner : corners) {
      const double side = nx * (corner[0] - p.x) + ny * (corner[1] - p.y);
      // The box is on the other side of edge pq than the triangle's third vertex.
      if (side * tri_side >= 0) all_outside = false;
    }
    if (all_outside) return false;
  }
  return true;
}

// Reads the triangles that meet a window: seeds from the blocks under it and from the
// triangles holding its centre and corners, then a walk across neighbours that meet it.
class WindowReader {
 public:
  WindowReader(Store& store, const SurfaceInfo& surface, const Box& box)
      : store_(store), surface_(surface), tables_(store.db(), surface), box_(box) {}

  Result<LoadedSurface> Read() {
    TB_RETURN_IF_ERROR(SeedFromBlocks());
    TB_RETURN_IF_ERROR(SeedFromPoints());
    while (!queue_.empty()) {
      const int64_t id = queue_.front();
      queue_.pop_front();
      TB_RETURN_IF_ERROR(Visit(id));
    }
    return std::move(out_);
  }

 private:
  Status SeedFromBlocks() {
    const BlockGrid& g = surface_.blocks;
    const int64_t bx0 = g.ColumnOf(box_.min_x);
    const int64_t bx1 = g.ColumnOf(box_.max_x);
    for (int64_t by = g.RowOf(box_.min_y); by <= g.RowOf(box_.max_y); ++by) {
      TB_ASSIGN_OR_RETURN(const auto ids, tables_.TriangleIdsAndBlocks(BlockGrid::Pack(bx0, by),
                                                                       BlockGrid::Pack(bx1, by)));
      for (const auto& [id, block] : ids) Enqueue(id);
    }
    return Status::Ok();
  }

  Status SeedFromPoints() {
    const double cx = (box_.min_x + box_.max_x) / 2;
    const double cy = (box_.min_y + box_.max_y) / 2;
    const std::array<std::array<double, 2>, 5> points = {{{cx, cy},
                                                          {box_.min_x, box_.min_y},
                                                          {box_.max_x, box_.min_y},
                                                          {box_.max_x, box_.max_y},
                                                          {box_.min_x, box_.max_y}}};
    PointLocator locator(store_, surface_);
    for (const auto& p : points) {
      Result<Location> at = locator.LocateTriangle(p[0], p[1]);
      if (at.ok()) {
        Enqueue(at->triangle);
      } else if (at.status().code() != StatusCode::kNotFound) {
        return at.status();
      }
    }
    return Status::Ok();
  }

  void Enqueue(int64_t id) {
    if (seen_.insert(id).second) queue_.push_back(id);
  }

  Status Visit(int64_t id) {
    TB_ASSIGN_OR_RETURN(const TriangleRow row, tables_.Triangle(id));
    TinTriangle t;
    for (int i = 0; i < 3; ++i) {
      TB_ASSIGN_OR_RETURN(t.v[i], VertexIndex(row.v[i]));
    }
    const auto& vs = out_.tin.vertices;
    if (!TriangleMeetsBox(vs[t.v[0]], vs[t.v[1]], vs[t.v[2]], box_)) return Status::Ok();
    t.visible = row.visible;
    if (row.tag) {
      TB_ASSIGN_OR_RETURN(t.tag, TagIndex(*row.tag));
    }
    out_.tin.triangles.push_back(t);
    out_.triangle_ids.push_back(id);
    for (const auto& n : row.n)
      if (n) Enqueue(*n);
    return Status::Ok();
  }

  Result<uint32_t> VertexIndex(int64_t id) {
    if (auto it = vertex_index_.find(id); it != vertex_index_.end()) return it->second;
    Result<VertexRow> v = tables_.Vertex(id);
    if (v.status().code() == StatusCode::kNotFound)
      return Status::Corruption("vertex " + std::to_string(id) + " is used but missing");
    if (!v.ok()) return v.status();
    const auto index = static_cast<uint32_t>(out_.tin.vertices.size());
    out_.tin.vertices.push_back(*v);
    out_.vertex_ids.push_back(id);
    vertex_index_.emplace(id, index);
    return index;
  }

  Result<int32_t> TagIndex(int64_t id) {
    if (auto it = tag_index_.find(id); it != tag_index_.end()) return it->second;
    TB_ASSIGN_OR_RETURN(std::string value, tables_.TagValue(id));
    const auto index = static_cast<int32_t>(out_.tin.tags.size());
    out_.tin.tags.push_back(std::move(value));
    tag_index_.emplace(id, index);
    return index;
  }

  Store& store_;
  const SurfaceInfo& surface_;
  MeshTables tables_;
  Box box_;
  LoadedSurface out_;
  std::deque<int64_t> queue_;
  std::unordered_set<int64_t> seen_;
  std::unordered_map<int64_t, uint32_t> vertex_index_;
  std::unordered_map<int64_t, int32_t> tag_index_;
};

bool Keep(const Tin& tin, const TinTriangle& t, const SurfaceFilter& filter) {
  if (filter.visible_only && !t.visible) return false;
  if (filter.tag && (t.tag == kNoTag || tin.tags[t.tag] != *filter.tag)) return false;
  if (filter.bbox) {
    const auto& v = tin.vertices;
    if (!TriangleMeetsBox(v[t.v[0]], v[t.v[1]], v[t.v[2]], *filter.bbox)) return false;
  }
  return true;
}

// The kept triangles of `in` in store id order, with only the vertices and tags they use and
// their neighbours linked among themselves.
Result<LoadedSurface> Compact(LoadedSurface in, const SurfaceFilter& filter) {
  std::vector<size_t> order;
  for (size_t t = 0; t < in.tin.triangles.size(); ++t)
    if (Keep(in.tin, in.tin.triangles[t], filter)) order.push_back(t);
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return in.triangle_ids[a] < in.triangle_ids[b]; });
  std::vector<uint32_t> used;
  for (size_t t : order)
    for (uint32_t v : in.tin.triangles[t].v) used.push_back(v);
  std::sort(used.begin(), used.end(),
            [&](uint32_t a, uint32_t b) { return in.vertex_ids[a] < in.vertex_ids[b]; });
  used.erase(std::unique(used.begin(), used.end()), used.end());

  LoadedSurface out;
  std::vector<int64_t> vertex_remap(in.tin.vertices.size(), -1);
  for (uint32_t v : used) {
    vertex_remap[v] = static_cast<int64_t>(out.tin.vertices.size());
    out.tin.vertices.push_back(in.tin.vertices[v]);
    out.vertex_ids.push_back(in.vertex_ids[v]);
  }
  std::vector<int32_t> tag_remap(in.tin.tags.size(), kNoTag);
  for (size_t t : order) {
    TinTriangle tri = in.tin.triangles[t];
    for (uint32_t& v : tri.v) v = static_cast<uint32_t>(vertex_remap[v]);
    if (tri.tag != kNoTag) {
      if (tag_remap[tri.tag] == kNoTag) {
        tag_remap[tri.tag] = static_cast<int32_t>(out.tin.tags.size());
        out.tin.tags.push_back(in.tin.tags[tri.tag]);
      }
      tri.tag = tag_remap[tri.tag];
    }
    out.tin.triangles.push_back(tri);
    out.triangle_ids.push_back(in.triangle_ids[t]);
  }
  for (const auto& [a, b] : in.tin.constraints)
    if (vertex_remap[a] >= 0 && vertex_remap[b] >= 0)
      out.tin.constraints.emplace_back(vertex_remap[a], vertex_remap[b]);
  if (!LinkNeighbours(out.tin))
    return Status::Corruption("the selected triangles overlap (tinbase check tells more)");
  return out;
}

Result<LoadedSurface> ReadCandidates(Store& store, const SurfaceInfo& surface,
                                     const SurfaceFilter& filter) {
  if (filter.feature != 0) {
    // Membership first, so a feature of another surface is named as such.
    TB_RETURN_IF_ERROR(LoadFeature(store, surface, filter.feature).status());
    return LoadFeatureSurface(store, filter.feature);
  }
  if (filter.bbox) return WindowReader(store, surface, *filter.bbox).Read();
  return SurfaceStore(store).Load(surface);
}

}  // namespace

std::string SurfaceFilter::Describe() const {
  std::vector<std::string> parts;
  if (bbox) parts.push_back("bbox " + Coordinates(*bbox));
  if (feature != 0) parts.push_back("feature " + std::to_string(feature));
  if (visible_only) parts.emplace_back("visible only");
  if (tag) parts.push_back("tag '" + *tag + "'");
  if (parts.empty()) return "everything";
  std::string out = parts[0];
  for (size_t i = 1; i < parts.size(); ++i) out += ", " + parts[i];
  return out;
}

Result<LoadedSurface> SelectSurface(Store& store, const SurfaceInfo& surface,
                                    const SurfaceFilter& filter) {
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  TB_ASSIGN_OR_RETURN(LoadedSurface candidates, ReadCandidates(store, surface, filter));
  TB_ASSIGN_OR_RETURN(LoadedSurface selected, Compact(std::move(candidates), filter));
  if (selected.tin.triangles.empty())
    return Status::NotFound("nothing selected: surface '" + surface.name +
                            "' has no triangles for " + filter.Describe());
  return selected;
}

Result<Box> ParseBbox(const std::string& text) {
  std::string spaced = text;
  std::replace(spaced.begin(), spaced.end(), ',', ' ');
  std::array<double, 4> v{};
  const char* p = spaced.c_str();
  for (double& value : v) {
    char* end = nullptr;
    value = std::strtod(p, &end);
    if (end == p || CheckNumber(value))
      return Status::InvalidArgument("bbox '" + text + "': expected minx,miny,maxx,maxy");
    p = end;
  }
  while (*p == ' ') ++p;
  if (*p != '\0')
    return Status::InvalidArgument("bbox '" + text + "': expected minx,miny,maxx,maxy");
  if (v[0] > v[2] || v[1] > v[3])
    return Status::InvalidArgument("bbox '" + text + "': min is above max");
  Box box;
  box.min_x = v[0], box.min_y = v[1], box.max_x = v[2], box.max_y = v[3];
  return box;
}

}  // namespace tinbase
