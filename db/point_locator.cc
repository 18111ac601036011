#include "db/point_locator.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cstdlib>
#include <random>
#include <unordered_map>

#include "core/geometry/predicates.h"
#include "db/mesh/mesh_tables.h"

namespace tinbase {

namespace {

// Rings of blocks searched around an empty block before settling for any triangle: the walk
// from a triangle a few blocks away is still short, and beyond that an arbitrary start is as good.
constexpr int kJumpRings = 3;
// Blocks (of about 32 triangles) between two points within which the second walk starts where
// the first ended rather than with a jump: a few blocks' walk is as short as a jump's.
constexpr int64_t kNearBlocks = 2;

struct WalkVertex {
  Point2 p;
  double z = 0;
};

// Reads the rows a walk touches, one by id, remembering vertices (consecutive triangles share
// two of them).
class WalkReader {
 public:
  WalkReader(Store& store, const SurfaceInfo& surface)
      : tables_(store.db(), surface), surface_(surface) {}

  Result<TriangleRow> Triangle(int64_t id) {
    Result<TriangleRow> row = tables_.Triangle(id);
    if (row.status().code() == StatusCode::kNotFound)
      return Status::Corruption(Where() + ": the walk reached triangle " + std::to_string(id) +
                                ", which does not exist; run tinbase check");
    return row;
  }

  Result<bool> Exists(int64_t triangle) { return tables_.HasTriangle(triangle); }

  Result<WalkVertex> Vertex(int64_t id) {
    if (auto it = vertices_.find(id); it != vertices_.end()) return it->second;
    Result<VertexRow> row = tables_.Vertex(id);
    if (row.status().code() == StatusCode::kNotFound)
      return Status::Corruption(Where() + ": vertex " + std::to_string(id) +
                                " does not exist; run tinbase check");
    TB_RETURN_IF_ERROR(row.status());
    const WalkVertex v{{row->x, row->y}, row->z};
    vertices_.emplace(id, v);
    return v;
  }

  // The value of the triangle's tag; nullopt without tag, or when the tag is not a row of tags
  // (CheckStore reports that: unknown-tag).
  Result<std::optional<std::string>> TagOf(const TriangleRow& t) {
    if (!t.tag) return std::optional<std::string>();
    Result<std::string> value = tables_.TagValue(*t.tag);
    if (value.status().code() == StatusCode::kNotFound) return std::optional<std::string>();
    TB_RETURN_IF_ERROR(value.status());
    return std::optional<std::string>(std::move(*value));
  }

  MeshTables& tables() { return tables_; }
  std::string Where() const { return "surface '" + surface_.name + "'"; }

 private:
  MeshTables tables_;
  const SurfaceInfo& surface_;
  std::unordered_map<int64_t, WalkVertex> vertices_;
};

// A triangle near (x, y): one in the point's block, else in the nearest non-empty ring of blocks
// around it, else any.
Result<int64_t> JumpStart(MeshTables& tables, const SurfaceInfo& surface, double x, double y) {
  const BlockGrid& grid = surface.blocks;
  const int64_t bx = grid.ColumnOf(x), by = grid.RowOf(y);
  for (int64_t r = 0; r <= kJumpRings; ++r) {
    for (int64_t dy = -r; dy <= r; ++dy) {
      for (int64_t dx = -r; dx <= r; ++dx) {
        if (std::max(std::abs(dx), std::abs(dy)) != r) continue;  // ring r only
        const int64_t cx = bx + dx, cy = by + dy;
        if (cx < 0 || cy < 0 || cx >= BlockGrid::kStride || cy >= BlockGrid::kStride) continue;
        TB_ASSIGN_OR_RETURN(auto id, tables.AnyTriangleInBlock(BlockGrid::Pack(cx, cy)));
        if (id) return *id;
      }
    }
  }
  TB_ASSIGN_OR_RETURN(std::optional<int64_t> any, tables.AnyTriangle());
  if (!any) return Status::NotFound("surface '" + surface.name + "' has no triangles");
  return *any;
}

double InterpolateZ(const std::array<WalkVertex, 3>& t, double x, double y) {
  return PlaneZ({t[0].p, t[1].p, t[2].p}, {t[0].z, t[1].z, t[2].z}, x, y);
}

// Shortest text that reads back as the same double, so a reported point can be located again.
std::string Number(double v) {
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  return std::string(buf, end);
}

std::string PointText(double x, double y) {
  std::string text = "(";
  text += Number(x);
  text += ", ";
  text += Number(y);
  return text + ")";
}

}  // namespace

double PlaneZ(const std::array<Point2, 3>& p, const std::array<double, 3>& z, double x, double y) {
  const double bx = p[1].x - p[0].x, by = p[1].y - p[0].y;
  const double cx = p[2].x - p[0].x, cy = p[2].y - p[0].y;
  const double px = x - p[0].x, py = y - p[0].y;
  const double det = bx * cy - by * cx;
  if (det == 0) return z[0];  // degenerate; CheckStore reports it
  const double l1 = (px * cy - py * cx) / det;
  const double l2 = (bx * py - by * px) / det;
  return z[0] + l1 * (z[1] - z[0]) + l2 * (z[2] - z[0]);
}

class PointLocator::Walker {
 public:
  Walker(Store& store, const SurfaceInfo& surface, MeshCache* cache)
      : store_(store), surface_(surface), reader_(store, surface), cache_(cache) {}

  Result<Location> Locate(double x, double y, bool paint) {
    TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store_));
    TB_ASSIGN_OR_RETURN(int64_t start, Start(x, y));
    TB_ASSIGN_OR_RETURN(Location location, Walk(start, x, y));
    last_ = location.triangle;
    last_point_ = Point2{x, y};
    if (!paint) return location;
    TB_ASSIGN_OR_RETURN(const TriangleRow found, reader_.Triangle(location.triangle));
    location.visible = found.visible;
    TB_ASSIGN_OR_RETURN(location.tag, reader_.TagOf(found));
    return location;
  }

 private:
  // Whether (x, y) is within kNearBlocks blocks of the previous point: then the walk from where
  // that one ended is short; from farther (random input, say) it would cross the surface, and a
  // jump costs one indexed lookup and a walk within a block.
  bool NearLast(double x, double y) const {
    const BlockGrid& g = surface_.blocks;
    return std::abs(g.ColumnOf(x) - g.ColumnOf(last_point_->x)) <= kNearBlocks &&
           std::abs(g.RowOf(y) - g.RowOf(last_point_->y)) <= kNearBlocks;
  }

  // Where the previous walk ended, while that triangle still exists and the point is near the
  // previous one; else a jump.
  Result<int64_t> Start(double x, double y) {
    if (last_ && NearLast(x, y)) {
      bool exists = false;
      if (cache_) {
        TB_ASSIGN_OR_RETURN(exists, cache_->HasTriangle(*last_));
      } else {
        TB_ASSIGN_OR_RETURN(exists, reader_.Exists(*last_));
      }
      if (exists) return *last_;
    }
    return JumpStart(reader_.tables(), surface_, x, y);
  }

  Result<Location> Walk(int64_t current, double x, double y) {
    const Point2 p{x, y};
    // Seeded by the point, so a query repeats exactly (and a failure reproduces).
    std::minstd_rand rng(
        static_cast<uint32_t>(std::bit_cast<uint64_t>(x) * 31 ^ std::bit_cast<uint64_t>(y)) | 1u);
    std::optional<int64_t> came_from;
    // On a valid triangulation the walk ends with probability 1 (Devillers, Pion, Teillaud,
    // "Walking in a triangulation"); broken links can make it cycle, so give up eventually.
    int64_t step_limit = int64_t{1} << 16;
    bool limit_checked = false;
    Location location;
    for (;;) {
      ++location.steps;
      if (location.steps > step_limit) {
        if (limit_checked)
          return Status::Corruption(reader_.Where() + ": the walk to " + PointText(x, y) +
                                    " does not end; run tinbase check");
        TB_ASSIGN_OR_RETURN(const MeshCounts counts, reader_.tables().Count());
        step_limit = std::max(step_limit, 4 * counts.triangles + 16);
        limit_checked = true;
      }
      TriangleRow tri;
      std::array<WalkVertex, 3> corner;
      if (cache_) {
        TB_ASSIGN_OR_RETURN(const TriangleRow* t, cache_->Triangle(current));
        tri = *t;
        for (int i = 0; i < 3; ++i) {
          TB_ASSIGN_OR_RETURN(const TinVertex* v, cache_->Vertex(tri.v[i]));
          corner[i] = {{v->x, v->y}, v->z};
        }
      } else {
        TB_ASSIGN_OR_RETURN(tri, reader_.Triangle(current));
        for (int i = 0; i < 3; ++i) {
          TB_ASSIGN_OR_RETURN(corner[i], reader_.Vertex(tri.v[i]));
        }
      }
      // Test the edges from a random one; the edge we came through has p on its inner side
      // (it was strictly outside it from the other triangle), so it needs no test.
      const int first = static_cast<int>(rng() % 3);
      std::optional<int> exit_edge;
      for (int k = 0; k < 3 && !exit_edge; ++k) {
        const int i = (first + k) % 3;
        if (came_from && tri.n[i] == came_from) continue;
        if (Orientation(corner[(i + 1) % 3].p, corner[(i + 2) % 3].p, p) < 0) exit_edge = i;
      }
      if (!exit_edge) {
        // The skipped edge holds p inside only if the links are symmetric; check, so broken
        // links give an error rather than a wrong triangle.
        for (int i = 0; i < 3; ++i) {
          if (came_from && tri.n[i] == came_from &&
              Orientation(corner[(i + 1) % 3].p, corner[(i + 2) % 3].p, p) < 0)
            return Status::Corruption(reader_.Where() + ": triangle " + std::to_string(current) +
                                      " and its neighbour " + std::to_string(*came_from) +
                                      " do not share the edge they link across; run tinbase "
                                      "check");
        }
        location.triangle = current;
        location.z = InterpolateZ(corner, x, y);
        return location;
      }
      const std::optional<int64_t> next = tri.n[*exit_edge];
      // Strictly beyond a boundary edge is outside because domains are convex: builders
      // triangulate the hull or the DEM's rectangle, and clip/erase hide triangles rather than
      // remove them. (On a non-convex domain a point across a notch would be called outside.)
      if (!next)
        return Status::NotFound("point " + PointText(x, y) + " is outside surface '" +
                                surface_.name + "'");
      came_from = current;
      current = *next;
    }
  }

  Store& store_;
  const SurfaceInfo& surface_;
  WalkReader reader_;
  MeshCache* cache_;  // when given, rows are read through it instead of reader_
  std::optional<int64_t> last_;
  std::optional<Point2> last_point_;  // the point whose walk ended in last_
};

PointLocator::PointLocator(Store& store, const SurfaceInfo& surface, MeshCache* cache)
    : walker_(std::make_unique<Walker>(store, surface, cache)) {}

PointLocator::~PointLocator() = default;

Result<Location> PointLocator::Locate(double x, double y) { return walker_->Locate(x, y, true); }

Result<Location> PointLocator::LocateTriangle(double x, double y) {
  return walker_->Locate(x, y, false);
}

Result<Location> LocatePoint(Store& store, const SurfaceInfo& surface, double x, double y) {
  PointLocator locator(store, surface);
  return locator.Locate(x, y);
}

}  // namespace tinbase
