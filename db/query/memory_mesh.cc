// MemoryMesh: see memory_mesh.h.
#include "db/query/memory_mesh.h"

#include <algorithm>
#include <limits>
#include <utility>

#include "db/mesh/mesh_tables.h"

namespace tinbase {

namespace {

// Positions of ascending ids. A surface's rows are written with consecutive ids, so the ids are
// usually dense and a table indexed by id - first answers in one load; ids left sparse by many
// edits fall back to a binary search.
class IdPositions {
 public:
  explicit IdPositions(const std::vector<int64_t>& ids) : ids_(ids) {
    if (ids.empty()) return;
    const int64_t span = ids.back() - ids.front() + 1;
    // A table at most a few times the rows' own ids costs no more memory than they do.
    if (span > 4 * static_cast<int64_t>(ids.size()) + 64) return;
    table_.assign(static_cast<size_t>(span), kAbsent);
    for (size_t i = 0; i < ids.size(); ++i)
      table_[static_cast<size_t>(ids[i] - ids.front())] = static_cast<uint32_t>(i);
  }

  std::optional<uint32_t> Find(int64_t id) const {
    if (ids_.empty() || id < ids_.front() || id > ids_.back()) return std::nullopt;
    if (!table_.empty()) {
      const uint32_t at = table_[static_cast<size_t>(id - ids_.front())];
      return at == kAbsent ? std::nullopt : std::optional<uint32_t>(at);
    }
    const auto it = std::lower_bound(ids_.begin(), ids_.end(), id);
    if (it == ids_.end() || *it != id) return std::nullopt;
    return static_cast<uint32_t>(it - ids_.begin());
  }

 private:
  static constexpr uint32_t kAbsent = std::numeric_limits<uint32_t>::max();
  const std::vector<int64_t>& ids_;
  std::vector<uint32_t> table_;
};

// Load's answer for rows that cannot be held by position.
Result<std::optional<MemoryMesh>> CannotHold() { return std::optional<MemoryMesh>(); }

// A triangle row as read, before its links become positions.
struct RawLinks {
  std::array<std::optional<int64_t>, 3> n;
};

}  // namespace

const std::optional<std::string>& MemoryMesh::Tag(uint32_t t) const {
  static const std::optional<std::string> kNone;
  const uint32_t tag = triangles_[t].paint & ~MemoryTriangle::kHidden;
  return tag == 0 ? kNone : tag_values_[tag - 1];
}

std::optional<uint32_t> MemoryMesh::FirstInBlock(int64_t packed_block) const {
  if (block_grid_.empty()) {
    const auto it = first_in_block_.find(packed_block);
    if (it == first_in_block_.end()) return std::nullopt;
    return it->second;
  }
  const int64_t col = BlockGrid::ColumnOfPacked(packed_block) - col0_;
  const int64_t row = BlockGrid::RowOfPacked(packed_block) - row0_;
  if (col < 0 || row < 0 || col >= cols_ || row >= rows_) return std::nullopt;
  const int32_t at = block_grid_[static_cast<size_t>(row * cols_ + col)];
  if (at < 0) return std::nullopt;
  return static_cast<uint32_t>(at);
}

void MemoryMesh::GridBlocks() {
  if (first_in_block_.empty()) return;
  int64_t col1 = 0, row1 = 0;
  col0_ = row0_ = BlockGrid::kStride;
  for (const auto& [block, t] : first_in_block_) {
    col0_ = std::min(col0_, BlockGrid::ColumnOfPacked(block));
    row0_ = std::min(row0_, BlockGrid::RowOfPacked(block));
    col1 = std::max(col1, BlockGrid::ColumnOfPacked(block));
    row1 = std::max(row1, BlockGrid::RowOfPacked(block));
  }
  cols_ = col1 - col0_ + 1;
  rows_ = row1 - row0_ + 1;
  // Builders size blocks for about 32 triangles over the surface's box, so the rectangle is about
  // as many cells as there are blocks; a surface whose blocks are scattered keeps the map.
  if (cols_ * rows_ > 4 * static_cast<int64_t>(first_in_block_.size()) + 64) return;
  block_grid_.assign(static_cast<size_t>(cols_ * rows_), -1);
  for (const auto& [block, t] : first_in_block_) {
    const int64_t col = BlockGrid::ColumnOfPacked(block) - col0_;
    const int64_t row = BlockGrid::RowOfPacked(block) - row0_;
    block_grid_[static_cast<size_t>(row * cols_ + col)] = static_cast<int32_t>(t);
  }
  first_in_block_.clear();
}

Result<std::optional<MemoryMesh>> MemoryMesh::Load(Store& store, const SurfaceInfo& surface) {
  MeshTables tables(store.db(), surface);
  MemoryMesh mesh;

  std::vector<int64_t> vertex_ids;
  std::vector<VertexRow> vertices;
  {
    TB_ASSIGN_OR_RETURN(VertexCursor cursor, tables.Vertices());
    int64_t id = 0;
    VertexRow row;
    for (;;) {
      TB_ASSIGN_OR_RETURN(const bool more, cursor.Next(&id, &row));
      if (!more) break;
      vertex_ids.push_back(id);
      vertices.push_back(row);
    }
  }
  const IdPositions vertex_at(vertex_ids);

  TB_ASSIGN_OR_RETURN(const auto tag_values, tables.TagValues());
  std::unordered_map<int64_t, uint32_t> tag_at;
  std::vector<RawLinks> links;
  {
    TB_ASSIGN_OR_RETURN(TriangleCursor cursor, tables.Triangles());
    int64_t id = 0;
    TriangleRow row;
    for (;;) {
      TB_ASSIGN_OR_RETURN(const bool more, cursor.Next(&id, &row));
      if (!more) break;
      if (mesh.triangles_.size() >= static_cast<size_t>(std::numeric_limits<int32_t>::max()))
        return CannotHold();
      const auto position = static_cast<uint32_t>(mesh.triangles_.size());
      MemoryTriangle t;
      std::array<double, 3> z{};
      for (int i = 0; i < 3; ++i) {
        const std::optional<uint32_t> v = vertex_at.Find(row.v[i]);
        if (!v) return CannotHold();
        t.p[i] = {vertices[*v].x, vertices[*v].y};
        z[i] = vertices[*v].z;
      }
      if (!row.visible) t.paint = MemoryTriangle::kHidden;
      if (row.tag) {
        auto [it, added] = tag_at.try_emplace(*row.tag, static_cast<uint32_t>(tag_at.size() + 1));
        if (added) {
          if (it->second >= MemoryTriangle::kHidden) return CannotHold();
          const auto value = tag_values.find(*row.tag);
          mesh.tag_values_.push_back(
              value == tag_values.end() ? std::nullopt : std::optional<std::string>(value->second));
        }
        t.paint |= it->second;
      }
      mesh.triangles_.push_back(t);
      mesh.heights_.push_back(z);
      links.push_back({row.n});
      mesh.triangle_ids_.push_back(id);
      // Rows come in id order, so the first row of a block is its lowest id.
      mesh.first_in_block_.try_emplace(row.block, position);
    }
  }

  const IdPositions triangle_at(mesh.triangle_ids_);
  for (size_t t = 0; t < links.size(); ++t) {
    for (int i = 0; i < 3; ++i) {
      const std::optional<int64_t>& n = links[t].n[i];
      if (!n) {
        mesh.triangles_[t].n[i] = MemoryTriangle::kBoundary;
        continue;
      }
      const std::optional<uint32_t> at = triangle_at.Find(*n);
      if (!at) return CannotHold();
      mesh.triangles_[t].n[i] = static_cast<int32_t>(*at);
    }
  }

  TB_ASSIGN_OR_RETURN(const std::optional<int64_t> any, tables.AnyTriangle());
  if (any) {
    mesh.any_ = triangle_at.Find(*any);
    if (!mesh.any_) return CannotHold();
  }
  mesh.GridBlocks();
  return std::optional<MemoryMesh>(std::move(mesh));
}

}  // namespace tinbase
