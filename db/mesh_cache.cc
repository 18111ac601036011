#include "db/mesh_cache.h"

#include <algorithm>
#include <limits>
#include <string>

#include "db/edit/mesh_delta.h"

namespace tinbase {

namespace {

MeshCache::Edge Key(int64_t a, int64_t b) { return {std::min(a, b), std::max(a, b)}; }

const std::vector<int64_t>& NoOwners() {
  static const std::vector<int64_t> none;
  return none;
}

}  // namespace

Result<int64_t> MeshCache::DataVersion() { return store_.db().DataVersion(); }

Result<bool> MeshCache::Begin(int64_t tx) {
  const bool was_current = committed_tx_ >= 0 && tx == committed_tx_ + 1;
  const int64_t seen = data_version_;
  committed_tx_ = -1;
  // Read inside the edit's transaction: this connection's own commit leaves the value as it is,
  // so Committed() needs no read transaction of its own after the commit (which would contend
  // with the checkpointer for the WAL's read locks).
  auto version = DataVersion();
  if (!version.ok()) {
    Clear();
    return version.status();
  }
  pending_version_ = *version;
  if (!was_current || *version != seen || triangles_.size() > kMaxKeptTriangles ||
      triangles_.bytes() + vertices_.bytes() > kMaxKeptBytes) {
    Clear();
    pending_version_ = *version;
    return false;
  }
  if (!owners_complete_) {
    if (Status s = LoadOwnersIfFew(); !s.ok()) {
      Clear();
      return s;
    }
  }
  return true;
}

void MeshCache::Committed(int64_t tx) {
  committed_tx_ = tx;
  data_version_ = store_.db().DataVersionAfterCommit(pending_version_, tx);
}

void MeshCache::Clear() {
  ForgetAllRows();
  committed_tx_ = -1;
  data_version_ = -1;
  pending_version_ = -1;
}

void MeshCache::ForgetAllRows() {
  whole_surface_ = false;
  triangles_.Clear();
  block_members_.clear();
  vertices_.Clear();
  ForgetAllOwners();
}

void MeshCache::ForgetTriangle(int64_t id) {
  const TriangleRow* cached = triangles_.Find(id);
  if (cached == nullptr) return;  // then its block is not kept either
  if (auto members = block_members_.find(cached->block); members != block_members_.end()) {
    std::vector<int64_t>& ids = members->second;
    const auto at = std::lower_bound(ids.begin(), ids.end(), id);
    if (at != ids.end() && *at == id) ids.erase(at);
  }
  triangles_.Erase(id);
}

void MeshCache::PutTriangle(int64_t id, const TriangleRow& t) {
  if (!triangles_.Put(id, t)) return;  // a row rewritten in place keeps its block
  if (auto members = block_members_.find(t.block); members != block_members_.end()) {
    std::vector<int64_t>& ids = members->second;
    ids.insert(std::lower_bound(ids.begin(), ids.end(), id), id);
  }
}

void MeshCache::Repaint(int64_t id, bool visible, const std::optional<int64_t>& tag) {
  if (TriangleRow* cached = triangles_.Find(id)) {
    cached->visible = visible;
    cached->tag = tag;
  }
}

void MeshCache::AddOwner(int64_t a, int64_t b, int64_t feature) {
  const Edge e = Key(a, b);
  if (auto it = owners_.find(e); it != owners_.end()) {
    it->second.push_back(feature);
  } else if (owners_complete_ || KnowsOwnersOf(e.first)) {
    owners_.emplace(e, std::vector<int64_t>{feature});
  }  // else unknown: its rows are read when next asked for
}

void MeshCache::SetUnconstrained(int64_t a, int64_t b) {
  // A complete map says "unconstrained" by not holding the edge; an entry per edge would make it
  // hold every edge the edits wrote, and every lookup slower.
  const Edge e = Key(a, b);
  if (owners_complete_ || KnowsOwnersOf(e.first))
    owners_.erase(e);
  else
    owners_[e].clear();
}

void MeshCache::ForgetAllOwners() {
  owners_.clear();
  owners_complete_ = false;
  owner_ranges_.clear();
}

Result<const TriangleRow*> MeshCache::Triangle(int64_t id) {
  if (const TriangleRow* cached = triangles_.Find(id)) return cached;
  Result<TriangleRow> row = tables_.Triangle(id);
  if (row.status().code() == StatusCode::kNotFound)
    return Status::Corruption("surface '" + surface_.name + "': triangle " + std::to_string(id) +
                              " is linked but missing");
  TB_RETURN_IF_ERROR(row.status());
  return &triangles_.Emplace(id, *row);
}

Result<bool> MeshCache::HasTriangle(int64_t id) {
  if (triangles_.Contains(id)) return true;
  return tables_.HasTriangle(id);
}

Result<const TinVertex*> MeshCache::Vertex(int64_t id) {
  if (const TinVertex* cached = vertices_.Find(id)) return cached;
  Result<VertexRow> row = tables_.Vertex(id);
  if (row.status().code() == StatusCode::kNotFound)
    return Status::Corruption("surface '" + surface_.name + "': vertex " + std::to_string(id) +
                              " is used but missing");
  TB_RETURN_IF_ERROR(row.status());
  return &vertices_.Emplace(id, *row);
}

Result<Point2> MeshCache::At(int64_t vertex) {
  TB_ASSIGN_OR_RETURN(const TinVertex* v, Vertex(vertex));
  return Point2{v->x, v->y};
}

Result<const std::vector<int64_t>*> MeshCache::Owners(int64_t a, int64_t b) {
  const Edge e = Key(a, b);
  if (auto it = owners_.find(e); it != owners_.end()) return &it->second;
  if (owners_complete_ || KnowsOwnersOf(e.first)) return &NoOwners();
  TB_ASSIGN_OR_RETURN(std::vector<int64_t> owners, tables_.Owners(e.first, e.second));
  return &owners_.emplace(e, std::move(owners)).first->second;
}

Result<std::vector<MeshCache::Edge>> MeshCache::EdgesOf(int64_t feature) {
  TB_ASSIGN_OR_RETURN(const std::vector<ConstraintRow> rows, tables_.ConstraintsOfFeature(feature));
  std::vector<Edge> edges;
  edges.reserve(rows.size());
  for (const ConstraintRow& c : rows) edges.push_back(Key(c.va, c.vb));
  return edges;
}

Result<std::vector<int64_t>> MeshCache::LoadSurface() {
  std::vector<int64_t> ids;
  {
    TB_ASSIGN_OR_RETURN(TriangleCursor triangles, tables_.Triangles());
    int64_t id = 0;
    for (TriangleRow row;;) {
      TB_ASSIGN_OR_RETURN(bool more, triangles.Next(&id, &row));
      if (!more) break;
      if (!triangles_.Contains(id)) triangles_.Emplace(id, row);
      ids.push_back(id);
    }
  }
  // Every triangle is held now, so every block's members are known (ids ascending, as read).
  block_members_.clear();
  for (int64_t id : ids) block_members_[triangles_.Find(id)->block].push_back(id);
  {
    TB_ASSIGN_OR_RETURN(VertexCursor vertices, tables_.Vertices());
    int64_t id = 0;
    for (VertexRow row;;) {
      TB_ASSIGN_OR_RETURN(bool more, vertices.Next(&id, &row));
      if (!more) break;
      vertices_.Emplace(id, row);
    }
  }
  TB_RETURN_IF_ERROR(LoadOwners());
  whole_surface_ = true;
  return ids;
}

Status MeshCache::LoadOwners() {
  TB_ASSIGN_OR_RETURN(ConstraintCursor constraints, tables_.Constraints());
  owners_.clear();  // rebuilt whole: an entry read before holds the same owners
  for (ConstraintRow c;;) {
    TB_ASSIGN_OR_RETURN(bool more, constraints.Next(&c));
    if (!more) break;
    owners_[Key(c.va, c.vb)].push_back(c.feature.value_or(0));
  }
  owners_complete_ = true;
  return Status::Ok();
}

Result<int64_t> MeshCache::StoredConstraintRows() { return tables_.CountConstraints(); }

Status MeshCache::LoadOwnersIfFew() {
  TB_ASSIGN_OR_RETURN(const int64_t rows, StoredConstraintRows());
  if (rows > static_cast<int64_t>(kMaxKeptTriangles)) return Status::Ok();
  return LoadOwners();
}

Result<std::vector<int64_t>> MeshCache::TrianglesInBox(const Box& box) {
  const BlockGrid& g = surface_.blocks;
  const int64_t bx0 = g.ColumnOf(box.min_x), bx1 = g.ColumnOf(box.max_x);
  std::vector<int64_t> ids;
  for (int64_t by = g.RowOf(box.min_y); by <= g.RowOf(box.max_y); ++by)
    TB_RETURN_IF_ERROR(TrianglesInBlocks(by, bx0, bx1, &ids));
  return ids;
}

Status MeshCache::TrianglesInBlocks(int64_t by, int64_t bx0, int64_t bx1,
                                    std::vector<int64_t>* ids) {
  const int64_t first = BlockGrid::Pack(bx0, by), last = BlockGrid::Pack(bx1, by);
  bool kept = true;
  for (int64_t b = first; b <= last && kept; ++b) kept = block_members_.count(b) > 0;
  if (kept) {
    for (int64_t b = first; b <= last; ++b) {
      const std::vector<int64_t>& members = block_members_[b];
      ids->insert(ids->end(), members.begin(), members.end());
    }
    return Status::Ok();
  }
  TB_ASSIGN_OR_RETURN(TriangleCursor rows, tables_.TrianglesInBlocks(first, last));
  std::vector<std::vector<int64_t>> members(static_cast<size_t>(last - first + 1));
  int64_t id = 0;
  for (TriangleRow row;;) {
    TB_ASSIGN_OR_RETURN(bool more, rows.Next(&id, &row));
    if (!more) break;
    if (!triangles_.Contains(id)) triangles_.Emplace(id, row);
    members[static_cast<size_t>(row.block - first)].push_back(id);
    ids->push_back(id);
  }
  for (int64_t b = first; b <= last; ++b)
    block_members_[b] = std::move(members[static_cast<size_t>(b - first)]);
  return Status::Ok();
}

Status MeshCache::ReadBlocks(const std::vector<int64_t>& packed) {
  std::vector<int64_t> ids;
  for (size_t first = 0; first < packed.size();) {
    size_t last = first;
    const int64_t by = BlockGrid::RowOfPacked(packed[first]);
    while (last + 1 < packed.size() && packed[last + 1] == packed[last] + 1 &&
           BlockGrid::RowOfPacked(packed[last + 1]) == by)
      ++last;
    TB_RETURN_IF_ERROR(TrianglesInBlocks(by, BlockGrid::ColumnOfPacked(packed[first]),
                                         BlockGrid::ColumnOfPacked(packed[last]), &ids));
    first = last + 1;
  }
  return ReadVerticesOf(ids);
}

Status MeshCache::ReadVerticesOf(const std::vector<int64_t>& ids) {
  std::vector<int64_t> wanted;
  for (int64_t t : ids) {
    const TriangleRow* tri = triangles_.Find(t);
    if (tri == nullptr) continue;
    for (int64_t v : tri->v)
      if (!vertices_.Contains(v)) wanted.push_back(v);
  }
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
  for (size_t first = 0; first < wanted.size();) {
    size_t last = first;
    while (last + 1 < wanted.size() && wanted[last + 1] - wanted[last] < kGap) ++last;
    {
      TB_ASSIGN_OR_RETURN(VertexCursor range,
                          tables_.VerticesInIdRange(wanted[first], wanted[last]));
      int64_t id = 0;
      for (VertexRow row;;) {
        TB_ASSIGN_OR_RETURN(bool more, range.Next(&id, &row));
        if (!more) break;
        if (!vertices_.Contains(id)) vertices_.Emplace(id, row);
      }
    }
    if (!owners_complete_) TB_RETURN_IF_ERROR(ReadOwnersOf(wanted[first], wanted[last]));
    first = last + 1;
  }
  return Status::Ok();
}

bool MeshCache::KnowsOwnersOf(int64_t va) const {
  // The last range starting at or before va (ranges may overlap: a miss only costs a lookup).
  auto it = std::upper_bound(owner_ranges_.begin(), owner_ranges_.end(),
                             std::make_pair(va, std::numeric_limits<int64_t>::max()));
  return it != owner_ranges_.begin() && va <= std::prev(it)->second;
}

Status MeshCache::ReadOwnersOf(int64_t first, int64_t last) {
  TB_ASSIGN_OR_RETURN(ConstraintCursor rows, tables_.ConstraintsFrom(first, last));
  std::unordered_map<Edge, std::vector<int64_t>, EdgeHash> read;
  for (ConstraintRow c;;) {
    TB_ASSIGN_OR_RETURN(bool more, rows.Next(&c));
    if (!more) break;
    read[Key(c.va, c.vb)].push_back(c.feature.value_or(0));
  }
  // An edge already held is as stored (kept through the edits' writes).
  for (auto& [e, owners] : read) owners_.try_emplace(e, std::move(owners));
  // Past the bound the ranges are dropped (the owners read stay): a cache kept through a long
  // load over a surface with too many constraint rows to hold them all (LoadOwnersIfFew) would
  // otherwise gather ranges without end, and each insertion moves the ones after it.
  if (owner_ranges_.size() >= kMaxOwnerRanges) owner_ranges_.clear();
  const auto range = std::make_pair(first, last);
  owner_ranges_.insert(std::upper_bound(owner_ranges_.begin(), owner_ranges_.end(), range), range);
  return Status::Ok();
}

Result<std::vector<int64_t>> MeshCache::Star(int64_t vertex, int64_t start, bool* closed) {
  std::vector<int64_t> star;
  *closed = true;
  for (int direction : {1, 2}) {  // across edge (v, next) ccw, then (v, previous) cw
    int64_t t = start;
    for (size_t guard = 0; guard < 100000; ++guard) {
      TB_ASSIGN_OR_RETURN(const TriangleRow* tri, Triangle(t));
      int i = 0;
      while (i < 3 && tri->v[i] != vertex) ++i;
      if (i == 3)
        return Status::Corruption("surface '" + surface_.name + "': triangle " + std::to_string(t) +
                                  " is linked around vertex " + std::to_string(vertex) +
                                  " but does not use it");
      if (direction == 1 || t != start) star.push_back(t);
      const std::optional<int64_t> next = tri->n[(i + direction) % 3];
      if (!next) {
        *closed = false;
        break;
      }
      if (*next == start) return star;  // went all the way round
      t = *next;
    }
  }
  std::sort(star.begin(), star.end());
  star.erase(std::unique(star.begin(), star.end()), star.end());
  return star;
}

Status MeshCache::VerifyAgainstStore() {
  MeshCache fresh(store_, surface_);
  const std::string where = "surface '" + surface_.name + "': cached ";
  Status status;
  triangles_.ForEach([&](int64_t id, const TriangleRow& t) {
    if (!status.ok()) return;
    auto stored = fresh.Triangle(id);
    if (!stored.ok()) {
      status = Status::Corruption(where + "triangle " + std::to_string(id) + " is not stored");
      return;
    }
    const TriangleRow& s = **stored;
    if (s.v != t.v || s.n != t.n || s.visible != t.visible || s.tag != t.tag || s.block != t.block)
      status =
          Status::Corruption(where + "triangle " + std::to_string(id) + " differs from its row");
  });
  vertices_.ForEach([&](int64_t id, const TinVertex& v) {
    if (!status.ok()) return;
    auto stored = fresh.Vertex(id);
    if (!stored.ok()) {
      status = Status::Corruption(where + "vertex " + std::to_string(id) + " is not stored");
      return;
    }
    const TinVertex& s = **stored;
    if (s.x != v.x || s.y != v.y || s.z != v.z || s.kind != v.kind)
      status = Status::Corruption(where + "vertex " + std::to_string(id) + " differs from its row");
  });
  TB_RETURN_IF_ERROR(status);
  for (const auto& [block, members] : block_members_) {
    TB_ASSIGN_OR_RETURN(const std::vector<int64_t> stored, tables_.TriangleIdsInBlock(block));
    if (stored != members)
      return Status::Corruption(where + "members of block " + std::to_string(block) +
                                " differ from the triangle rows");
  }
  size_t owner_rows = 0;
  for (const auto& [e, owners] : owners_) {
    TB_ASSIGN_OR_RETURN(const std::vector<int64_t>* stored, fresh.Owners(e.first, e.second));
    std::vector<int64_t> a = owners, b = *stored;
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    if (a != b)
      return Status::Corruption(where + "owners of edge (" + std::to_string(e.first) + ", " +
                                std::to_string(e.second) + ") differ from the constraint rows");
    owner_rows += owners.size();
  }
  // In a known range too, an edge it lacks is unconstrained.
  for (const auto& [first, last] : owner_ranges_) {
    TB_ASSIGN_OR_RETURN(const int64_t count, tables_.CountConstraintsFrom(first, last));
    size_t known = 0;
    for (const auto& [e, owners] : owners_)
      if (e.first >= first && e.first <= last) known += owners.size();
    if (static_cast<int64_t>(known) != count)
      return Status::Corruption(where + "constraint rows from vertices " + std::to_string(first) +
                                " to " + std::to_string(last) + " are not all known");
  }
  if (!owners_complete_) return Status::Ok();
  // Complete, an edge it lacks is unconstrained: every stored row must be in it.
  TB_ASSIGN_OR_RETURN(const int64_t stored_rows, StoredConstraintRows());
  if (static_cast<int64_t>(owner_rows) != stored_rows)
    return Status::Corruption(where + "the constraint rows known (" + std::to_string(owner_rows) +
                              ") are not all the surface's (" + std::to_string(stored_rows) + ")");
  return Status::Ok();
}

void MeshCache::Apply(const MeshDelta& delta) {
  for (size_t k = 0; k < delta.new_vertices.size(); ++k)
    PutVertex(delta.first_vertex + static_cast<int64_t>(k), delta.new_vertices[k]);
  for (const VertexZ& v : delta.region_z) PutVertex(v.id, v.vertex);
  for (size_t k = 0; k < delta.new_triangles.size(); ++k)
    PutTriangle(delta.first_triangle + static_cast<int64_t>(k), delta.new_triangles[k]);
  if (!delta.whole_surface)
    for (int64_t t : delta.deleted_triangles) ForgetTriangle(t);
  for (int64_t v : delta.deleted_vertices) ForgetVertex(v);
  if (delta.whole_surface) ForgetAllRows();
  for (const auto& [id, t] : delta.relinked) PutTriangle(id, t);
  if (!delta.removed_features.empty()) ForgetAllOwners();
  for (const auto& e : delta.split_constraints) SetUnconstrained(e.first, e.second);
  for (const auto& [e, feature] : delta.added_constraints) AddOwner(e.first, e.second, feature);
  // The new triangles' other edges are unconstrained: said so, the next edits need not look
  // their rows up (a cache that knows every constraint needs no telling).
  if (!knows_every_constraint())
    for (const auto& e : delta.free_edges) SetUnconstrained(e.first, e.second);
  for (const TriangleRepaint& r : delta.repaints) Repaint(r.triangle, r.visible, r.tag);
  for (const TriangleRepaint& r : delta.block_repaints) Repaint(r.triangle, r.visible, r.tag);
  for (const VertexZ& v : delta.around_z) PutVertex(v.id, v.vertex);
}

}  // namespace tinbase
