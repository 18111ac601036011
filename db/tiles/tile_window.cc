// Tile window: see tile_window.h.
#include "db/tiles/tile_window.h"

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <set>
#include <unordered_map>
#include <vector>

#include "core/geometry/reproject.h"
#include "core/tiles/quantized_mesh.h"
#include "db/feature_store.h"
#include "db/mesh/mesh_tables.h"
#include "db/point_locator.h"

namespace tinbase {

namespace {

// The box, in the store's CRS, of the rectangle's image (its edges densified, so a curved image
// of a straight edge stays inside), grown by a hundredth of its size: where the seeds are read.
Result<Box> StoreBox(const Crs& crs, const Crs& wgs84, const TileRect& r) {
  constexpr int kSteps = 16;
  std::vector<TinVertex> ring;
  for (int i = 0; i <= kSteps; ++i) {
    const double t = static_cast<double>(i) / kSteps;
    const double lon = r.west + t * (r.east - r.west);
    const double lat = r.south + t * (r.north - r.south);
    for (const auto& [x, y] : {std::pair{lon, r.south}, std::pair{lon, r.north},
                               std::pair{r.west, lat}, std::pair{r.east, lat}})
      ring.push_back({x, y, 0, VertexKind::kDem});
  }
  TB_RETURN_IF_ERROR(ReprojectXy(wgs84, crs, ring));
  Box box;
  for (const TinVertex& v : ring) box.Add(Point2{v.x, v.y});
  const double grow = 0.01 * std::max(box.max_x - box.min_x, box.max_y - box.min_y);
  box.min_x -= grow, box.min_y -= grow, box.max_x += grow, box.max_y += grow;
  return box;
}

class WindowReader {
 public:
  WindowReader(Store& store, const SurfaceInfo& surface, const Crs& crs, const Crs& wgs84,
               const TileRect& rect, int level)
      : store_(store), surface_(surface), crs_(crs), wgs84_(wgs84), tables_(store.db(), surface) {
    const double step = TileDegrees(level) / kQuantizedMax;
    rect_ = {rect.west - step, rect.south - step, rect.east + step, rect.north + step};
  }

  Result<TileWindow> Read(const TileRect& rect) {
    TB_ASSIGN_OR_RETURN(const Box box, StoreBox(crs_, wgs84_, rect));
    std::vector<int64_t> frontier;
    TB_RETURN_IF_ERROR(SeedFromBlocks(box, &frontier));
    TB_RETURN_IF_ERROR(SeedFromPoints(box, &frontier));
    while (!frontier.empty()) {
      TB_RETURN_IF_ERROR(LoadVertices(/*geographic=*/true));
      std::vector<int64_t> next;
      for (const int64_t id : frontier) {
        const TriangleRow& row = triangles_.at(id);
        if (!MeetsRect(row)) continue;
        cut_.insert(id);
        for (const int64_t v : row.v) around_.insert(v);
        for (const auto& n : row.n)
          if (n) TB_RETURN_IF_ERROR(Request(*n, &next));
      }
      frontier = std::move(next);
    }
    TB_RETURN_IF_ERROR(ReadStars());
    TB_RETURN_IF_ERROR(LoadVertices(/*geographic=*/false));
    return Assemble();
  }

 private:
  Status SeedFromBlocks(const Box& box, std::vector<int64_t>* frontier) {
    const BlockGrid& g = surface_.blocks;
    const int64_t bx0 = g.ColumnOf(box.min_x);
    const int64_t bx1 = g.ColumnOf(box.max_x);
    for (int64_t by = g.RowOf(box.min_y); by <= g.RowOf(box.max_y); ++by) {
      TB_ASSIGN_OR_RETURN(
          TriangleCursor cursor,
          tables_.TrianglesInBlocks(BlockGrid::Pack(bx0, by), BlockGrid::Pack(bx1, by)));
      int64_t id = 0;
      TriangleRow row;
      while (true) {
        TB_ASSIGN_OR_RETURN(const bool more, cursor.Next(&id, &row));
        if (!more) break;
        if (triangles_.emplace(id, row).second) {
          frontier->push_back(id);
          fresh_.push_back(id);
        }
      }
    }
    return Status::Ok();
  }

  Status SeedFromPoints(const Box& box, std::vector<int64_t>* frontier) {
    const double cx = (box.min_x + box.max_x) / 2;
    const double cy = (box.min_y + box.max_y) / 2;
    const std::array<std::array<double, 2>, 5> points = {{{cx, cy},
                                                          {box.min_x, box.min_y},
                                                          {box.max_x, box.min_y},
                                                          {box.max_x, box.max_y},
                                                          {box.min_x, box.max_y}}};
    PointLocator locator(store_, surface_);
    for (const auto& p : points) {
      Result<Location> at = locator.LocateTriangle(p[0], p[1]);
      if (at.ok()) {
        TB_RETURN_IF_ERROR(Request(at->triangle, frontier));
      } else if (at.status().code() != StatusCode::kNotFound) {
        return at.status();
      }
    }
    return Status::Ok();
  }

  // Reads triangle `id` unless it was read already, and lists it in `*to` when it is new.
  Status Request(int64_t id, std::vector<int64_t>* to) {
    if (triangles_.count(id) > 0) return Status::Ok();
    Result<TriangleRow> row = tables_.Triangle(id);
    if (!row.ok()) {
      if (row.status().code() == StatusCode::kNotFound)
        return Status::Corruption("triangle " + std::to_string(id) + " is linked but missing");
      return row.status();
    }
    triangles_.emplace(id, *row);
    to->push_back(id);
    fresh_.push_back(id);
    return Status::Ok();
  }

  // Reads the rows of the vertices the read triangles use and that are not read yet, with their
  // geographic position when `geographic`: in id order, by one scan of their id range when they
  // fill a good part of it (a large window), else one lookup each.
  Status LoadVertices(bool geographic) {
    std::vector<int64_t> ids;
    for (const int64_t t : fresh_)
      for (const int64_t v : triangles_.at(t).v)
        if (vertices_.count(v) == 0) ids.push_back(v);
    fresh_.clear();
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    if (ids.empty()) return Status::Ok();
    std::vector<TinVertex> points;
    points.reserve(ids.size());
    constexpr int64_t kScanDensity = 8;  // a scan reads up to this many rows per wanted one
    if (static_cast<int64_t>(ids.size()) * kScanDensity >= ids.back() - ids.front() + 1) {
      TB_ASSIGN_OR_RETURN(VertexCursor cursor, tables_.VerticesInIdRange(ids.front(), ids.back()));
      size_t next = 0;
      int64_t id = 0;
      VertexRow row;
      while (true) {
        TB_ASSIGN_OR_RETURN(const bool more, cursor.Next(&id, &row));
        if (!more) break;
        while (next < ids.size() && ids[next] < id) ++next;
        if (next < ids.size() && ids[next] == id) points.push_back(row);
      }
    } else {
      for (const int64_t v : ids) {
        Result<VertexRow> vertex = tables_.Vertex(v);
        if (!vertex.ok()) {
          if (vertex.status().code() == StatusCode::kNotFound) break;
          return vertex.status();
        }
        points.push_back(*vertex);
      }
    }
    if (points.size() != ids.size())
      return Status::Corruption("a vertex used by a triangle of surface '" + surface_.name +
                                "' is missing (tinbase check tells more)");
    for (size_t i = 0; i < ids.size(); ++i) vertices_.emplace(ids[i], points[i]);
    if (!geographic) return Status::Ok();
    TB_RETURN_IF_ERROR(ReprojectXy(crs_, wgs84_, points));
    for (size_t i = 0; i < ids.size(); ++i) geographic_.emplace(ids[i], points[i]);
    return Status::Ok();
  }

  bool MeetsRect(const TriangleRow& row) const {
    double west = std::numeric_limits<double>::infinity(), south = west;
    double east = -west, north = -west;
    for (const int64_t v : row.v) {
      const TinVertex& p = geographic_.at(v);
      west = std::min(west, p.x), east = std::max(east, p.x);
      south = std::min(south, p.y), north = std::max(north, p.y);
    }
    return west <= rect_.east && rect_.west <= east && south <= rect_.north && rect_.south <= north;
  }

  // Every triangle around a vertex of the cut triangles: across each edge that ends at one of
  // those vertices, from the triangles already read, until nothing new is reached.
  Status ReadStars() {
    std::vector<int64_t> queue(cut_.begin(), cut_.end());
    std::set<int64_t> done(cut_.begin(), cut_.end());
    while (!queue.empty()) {
      const int64_t id = queue.back();
      queue.pop_back();
      const TriangleRow row = triangles_.at(id);
      for (int i = 0; i < 3; ++i) {
        if (!row.n[i]) continue;
        if (around_.count(row.v[(i + 1) % 3]) == 0 && around_.count(row.v[(i + 2) % 3]) == 0)
          continue;
        std::vector<int64_t> unused;
        TB_RETURN_IF_ERROR(Request(*row.n[i], &unused));
        if (done.insert(*row.n[i]).second) queue.push_back(*row.n[i]);
      }
    }
    return Status::Ok();
  }

  Result<TileWindow> Assemble() {
    TileWindow out;
    out.cut_triangles = static_cast<int64_t>(cut_.size());
    out.min_z = std::numeric_limits<double>::infinity();
    out.max_z = -out.min_z;
    std::unordered_map<int64_t, uint32_t> index;
    for (const auto& [id, vertex] : vertices_) {
      index.emplace(id, static_cast<uint32_t>(out.tin.vertices.size()));
      out.tin.vertices.push_back(vertex);
      out.min_z = std::min(out.min_z, vertex.z), out.max_z = std::max(out.max_z, vertex.z);
    }
    std::unordered_map<int64_t, int32_t> tags;
    for (const auto& [id, row] : triangles_) {
      TinTriangle t;
      for (int i = 0; i < 3; ++i) t.v[i] = index.at(row.v[i]);
      t.visible = row.visible;
      if (row.tag) {
        auto it = tags.find(*row.tag);
        if (it == tags.end()) {
          TB_ASSIGN_OR_RETURN(std::string value, tables_.TagValue(*row.tag));
          it = tags.emplace(*row.tag, static_cast<int32_t>(out.tin.tags.size())).first;
          out.tin.tags.push_back(std::move(value));
        }
        t.tag = it->second;
      }
      out.tin.triangles.push_back(t);
    }
    return out;
  }

  Store& store_;
  const SurfaceInfo& surface_;
  const Crs& crs_;
  const Crs& wgs84_;
  MeshTables tables_;
  TileRect rect_;  // the rectangle grown by one quantisation step
  std::map<int64_t, TriangleRow> triangles_;
  std::map<int64_t, VertexRow> vertices_;
  std::vector<int64_t> fresh_;  // triangles read since the last LoadVertices
  std::unordered_map<int64_t, TinVertex> geographic_;
  std::set<int64_t> cut_;     // triangles whose geographic box meets rect_
  std::set<int64_t> around_;  // their vertices
};

}  // namespace

TileRect RectOfRange(const TileRange& range) {
  const TileRect a = RectOf({range.level, range.x0, range.y0});
  const TileRect b = RectOf({range.level, range.x1, range.y1});
  return {a.west, a.south, b.east, b.north};
}

Result<TileWindow> ReadTileWindow(Store& store, const SurfaceInfo& surface, const Crs& crs,
                                  const TileRect& rect, int level) {
  TB_ASSIGN_OR_RETURN(const Crs wgs84, Crs::FromUserInput("EPSG:4326"));
  return WindowReader(store, surface, crs, wgs84, rect, level).Read(rect);
}

}  // namespace tinbase
