#include "db/feature_store.h"

#include <array>
#include <map>
#include <unordered_map>

#include "core/geometry/polygon_locator.h"
#include "core/tin/cell_cover.h"
#include "core/tin/ring_blocks.h"
#include "core/vector/feature_wkb.h"
#include "core/vector/line_z_wkb.h"
#include "core/vector/point_wkb.h"
#include "db/mesh/mesh_tables.h"

namespace tinbase {

namespace {

Result<std::vector<EditorFeature>> SelectFeatures(Store& store, const SurfaceInfo& surface,
                                                  std::optional<int64_t> only) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("SELECT f.id, f.name, f.mode, f.level, t.value, "
                                        "f.geometry, f.attributes, f.z_from FROM features f "
                                        "LEFT JOIN tags t "
                                        "ON t.id = f.tag WHERE f.surface = ?1 "
                                        "AND (CAST(?2 AS BIGINT) IS NULL OR f.id = ?2) "
                                        "ORDER BY f.id"));
  stmt->Bind(1, surface.id);
  if (only)
    stmt->Bind(2, *only);
  else
    stmt->BindNull(2);
  std::vector<EditorFeature> out;
  Status status = Status::Ok();
  while (true) {
    auto row = stmt->Step();
    if (!row.ok()) {
      status = row.status();
      break;
    }
    if (!*row) break;
    EditorFeature f;
    f.id = stmt->ColumnInt(0);
    f.label = "feature " + std::to_string(f.id);
    // The store's text is parsed here, once: past this row nothing compares mode strings.
    auto mode = ParseFeatureMode(stmt->ColumnText(2));
    if (!mode.ok()) {
      status = Status::Corruption(f.label + ": " + mode.status().message());
      break;
    }
    f.mode = *mode;
    if (!stmt->ColumnIsNull(3)) f.level = stmt->ColumnDouble(3);
    if (!stmt->ColumnIsNull(4)) f.tag = stmt->ColumnText(4);
    f.attributes = nlohmann::json::parse(stmt->ColumnText(6), nullptr, /*allow_exceptions=*/false);
    if (f.attributes.is_discarded()) f.attributes = nlohmann::json::object();
    size_t size = 0;
    const uint8_t* blob = stmt->ColumnBlob(5, &size);
    std::vector<uint8_t> wkb(blob, blob + size);
    auto z_from = ParseZFrom(stmt->ColumnText(7));
    if (!z_from.ok()) {
      status = Status::Corruption(f.label + ": " + z_from.status().message());
      break;
    }
    f.z_from = *z_from;
    if (IsLineMode(f.mode) && f.z_from == ZFrom::kFeature) {
      status = LinesZFromWkb(wkb, &f.lines, &f.line_z).WithContext(f.label);
      if (!status.ok()) break;
    } else if (IsLineMode(f.mode)) {
      auto lines = LinesFromWkb(wkb);
      if (!lines.ok()) {
        status = lines.status().WithContext(f.label);
        break;
      }
      f.lines = std::move(*lines);
    } else if (f.mode == FeatureMode::kPoints) {
      auto points = PointsFromWkb(wkb);
      if (!points.ok()) {
        status = points.status().WithContext(f.label);
        break;
      }
      f.points = std::move(*points);
    } else if (IsPolygonMode(f.mode)) {
      auto polygons = PolygonsFromWkb(wkb);
      if (!polygons.ok()) {
        status = polygons.status().WithContext(f.label);
        break;
      }
      f.polygons = std::move(*polygons);
    }
    out.push_back(std::move(f));
  }
  stmt->Reset();
  TB_RETURN_IF_ERROR(status);
  return out;
}

}  // namespace

Result<int64_t> InternTag(Store& store, const std::string& value) {
  TB_ASSIGN_OR_RETURN(
      Statement * insert,
      store.db().Cached("INSERT INTO tags(value) VALUES (?) ON CONFLICT (value) DO NOTHING"));
  insert->Bind(1, value);
  TB_RETURN_IF_ERROR(insert->Run());
  TB_ASSIGN_OR_RETURN(Statement * select, store.db().Cached("SELECT id FROM tags WHERE value = ?"));
  select->Bind(1, value);
  TB_ASSIGN_OR_RETURN(bool row, select->Step());
  if (!row) return Status::Corruption("tag '" + value + "' vanished");
  const int64_t id = select->ColumnInt(0);
  select->Reset();
  return id;
}

Box BoxOf(const EditorFeature& f) {
  if (f.box_cache) return *f.box_cache;
  Box box;
  for (const Polygon& p : f.polygons)
    for (const Point2& q : p.shell) box.Add(q);
  for (const auto& line : f.lines)
    for (const Point2& q : line) box.Add(q);
  for (const TinVertex& q : f.points) box.Add(Point2{q.x, q.y});
  f.box_cache = box;
  return box;
}

const std::shared_ptr<const PolygonLocator>& InsideOf(const EditorFeature& f) {
  if (!f.inside_cache) f.inside_cache = std::make_shared<const PolygonLocator>(f.polygons);
  return f.inside_cache;
}

const std::vector<int64_t>& RingBlocksOf(const EditorFeature& f, const BlockGrid& grid) {
  const BlockGrid& g = f.ring_blocks_grid;
  if (!f.ring_blocks_cache || g.origin_x != grid.origin_x || g.origin_y != grid.origin_y ||
      g.size != grid.size) {
    f.ring_blocks_cache =
        std::make_shared<const std::vector<int64_t>>(BlocksNearRings(grid, f.polygons));
    f.ring_blocks_grid = grid;
  }
  return *f.ring_blocks_cache;
}

Result<std::vector<EditorFeature>> LoadFeatures(Store& store, const SurfaceInfo& surface) {
  return SelectFeatures(store, surface, std::nullopt);
}

Result<EditorFeature> LoadFeature(Store& store, const SurfaceInfo& surface, int64_t id) {
  TB_ASSIGN_OR_RETURN(std::vector<EditorFeature> one, SelectFeatures(store, surface, id));
  if (one.empty())
    return Status::NotFound("surface '" + surface.name + "' has no feature " + std::to_string(id));
  return std::move(one.front());
}

Status WriteFeature(Store& store, const SurfaceInfo& surface, int64_t tx, EditorFeature& f) {
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      store.db().Cached("INSERT INTO features(surface, name, mode, level, tag, "
                        "attributes, geometry, min_x, min_y, max_x, max_y, tx, z_from) "
                        "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?) RETURNING id"));
  std::optional<int64_t> tag_id;
  if (f.tag) {
    TB_ASSIGN_OR_RETURN(tag_id, InternTag(store, *f.tag));
  }
  const bool own_z = IsLineMode(f.mode) && f.z_from == ZFrom::kFeature;
  const std::vector<uint8_t> wkb = own_z                            ? LinesZToWkb(f.lines, f.line_z)
                                   : IsLineMode(f.mode)             ? LinesToWkb(f.lines)
                                   : f.mode == FeatureMode::kPoints ? PointsToWkb(f.points)
                                                                    : PolygonsToWkb(f.polygons);
  const Box box = BoxOf(f);
  stmt->Bind(1, surface.id).Bind(2, f.tag.value_or(f.label)).Bind(3, FeatureModeName(f.mode));
  if (f.level)
    stmt->Bind(4, *f.level);
  else
    stmt->BindNull(4);
  if (tag_id)
    stmt->Bind(5, *tag_id);
  else
    stmt->BindNull(5);
  stmt->Bind(6, f.attributes.dump()).BindBlob(7, wkb.data(), wkb.size());
  stmt->Bind(8, box.min_x).Bind(9, box.min_y).Bind(10, box.max_x).Bind(11, box.max_y).Bind(12, tx);
  stmt->Bind(13, ZFromName(own_z ? ZFrom::kFeature : ZFrom::kDem));
  TB_ASSIGN_OR_RETURN(f.id, RunReturningId(*stmt));
  return Status::Ok();
}

Status DeleteFeature(Store& store, int64_t id) {
  TB_RETURN_IF_ERROR(MeshTables::DeleteConstraintsOfFeature(store.db(), id));
  TB_ASSIGN_OR_RETURN(Statement * feature, store.db().Cached("DELETE FROM features WHERE id = ?"));
  feature->Bind(1, id);
  return feature->Run();
}

Paint PaintFromFeatures(const std::vector<EditorFeature>& features, const Grid* dem, Tin& tin) {
  if (dem == nullptr) return PaintFromFeatures(features, static_cast<CellSource*>(nullptr), tin);
  GridCellSource source(*dem);
  return PaintFromFeatures(features, &source, tin);
}

Paint PaintFromFeatures(const std::vector<EditorFeature>& features, CellSource* dem, Tin& tin) {
  tin.tags.clear();
  Box reach;  // no feature outside it can hold a centroid or vertex of `tin`
  for (const TinVertex& v : tin.vertices) reach.Add(Point2{v.x, v.y});
  std::map<std::string, int32_t> tag_index;
  std::vector<PaintedFeature> painted;
  for (const EditorFeature& f : features) {
    // A feature away from `tin` paints nothing of it, but a clip feature anywhere still means
    // that clipping is on: it stays, with no polygons. (The box first: most features of a map
    // are away from an edit.)
    const bool near = BoxOf(f).Meets(reach);
    if (!near && f.mode != FeatureMode::kClip) continue;
    if (!IsPolygonMode(f.mode)) continue;
    PaintedFeature p;
    if (near) p.inside = InsideOf(f);
    p.mode = f.mode;
    p.level = f.level.value_or(0);
    if (f.tag) {
      auto [it, added] = tag_index.emplace(*f.tag, static_cast<int32_t>(tin.tags.size()));
      if (added) tin.tags.push_back(*f.tag);
      p.tag = it->second;
    }
    painted.push_back(std::move(p));
  }
  Paint paint = ComputePaint(tin, painted);
  if (dem != nullptr) {
    for (size_t t = 0; t < tin.triangles.size(); ++t)
      if (!TriangleOnData(*dem, tin, tin.triangles[t])) paint.visible[t] = 0;
  }
  return paint;
}

namespace {

// The id of the surface that holds `feature`; NotFound when there is no such feature.
Result<int64_t> SurfaceIdOfFeature(Store& store, int64_t feature) {
  TB_ASSIGN_OR_RETURN(Statement * owner,
                      store.db().Cached("SELECT surface FROM features WHERE id = ?"));
  owner->Bind(1, feature);
  TB_ASSIGN_OR_RETURN(bool found, owner->Step());
  const int64_t surface_id = found ? owner->ColumnInt(0) : 0;
  owner->Reset();
  if (!found) return Status::NotFound("no feature " + std::to_string(feature));
  return surface_id;
}

// Store ids -> indices into a LoadedSurface being built: each vertex and tag is read and appended
// on its first use.
class RowIndex {
 public:
  // REQUIRES: `tables` and `out` outlive this object.
  RowIndex(MeshTables& tables, LoadedSurface& out) : tables_(tables), out_(out) {}

  // The vertex's index in out.tin.vertices; Corruption when it is used but missing.
  Result<uint32_t> Vertex(int64_t id) {
    if (auto it = vertices_.find(id); it != vertices_.end()) return it->second;
    Result<VertexRow> v = tables_.Vertex(id);
    if (v.status().code() == StatusCode::kNotFound)
      return Status::Corruption("vertex " + std::to_string(id) + " is used but missing");
    TB_RETURN_IF_ERROR(v.status());
    vertices_.emplace(id, static_cast<uint32_t>(out_.tin.vertices.size()));
    out_.tin.vertices.push_back(*v);
    out_.vertex_ids.push_back(id);
    return vertices_.at(id);
  }

  // The tag's index in out.tin.tags; kNoTag for an id the tags table lacks (as no tag).
  Result<int32_t> Tag(int64_t id) {
    if (auto it = tags_.find(id); it != tags_.end()) return it->second;
    Result<std::string> value = tables_.TagValue(id);
    int32_t at = kNoTag;
    if (value.ok()) {
      at = static_cast<int32_t>(out_.tin.tags.size());
      out_.tin.tags.push_back(*value);
    } else if (value.status().code() != StatusCode::kNotFound) {
      return value.status();
    }
    tags_.emplace(id, at);
    return at;
  }

 private:
  MeshTables& tables_;
  LoadedSurface& out_;
  std::unordered_map<int64_t, uint32_t> vertices_;
  std::unordered_map<int64_t, int32_t> tags_;
};

// The triangle rows of blocks [first, last] with their ids, read whole: the vertex lookups that
// follow use statements of their own.
Result<std::vector<std::pair<int64_t, TriangleRow>>> TriangleRowsInBlocks(MeshTables& tables,
                                                                          int64_t first,
                                                                          int64_t last) {
  std::vector<std::pair<int64_t, TriangleRow>> rows;
  TB_ASSIGN_OR_RETURN(TriangleCursor cursor, tables.TrianglesInBlocks(first, last));
  int64_t id = 0;
  for (TriangleRow row;;) {
    TB_ASSIGN_OR_RETURN(bool more, cursor.Next(&id, &row));
    if (!more) break;
    rows.emplace_back(id, row);
  }
  return rows;
}

// The triangles of the blocks under `box` whose centroid is not outside `inside`, with their
// tags and the vertices of every triangle read (also of those left out).
Result<LoadedSurface> TrianglesInside(MeshTables& tables, const BlockGrid& g, const Box& box,
                                      const PolygonLocator& inside) {
  LoadedSurface out;
  RowIndex index(tables, out);
  const int64_t bx0 = g.ColumnOf(box.min_x), bx1 = g.ColumnOf(box.max_x);
  for (int64_t by = g.RowOf(box.min_y); by <= g.RowOf(box.max_y); ++by) {
    TB_ASSIGN_OR_RETURN(const auto rows, TriangleRowsInBlocks(tables, BlockGrid::Pack(bx0, by),
                                                              BlockGrid::Pack(bx1, by)));
    for (const auto& [id, row] : rows) {
      TinTriangle t;
      for (int i = 0; i < 3; ++i) {
        TB_ASSIGN_OR_RETURN(t.v[i], index.Vertex(row.v[i]));
      }
      const TinVertex &a = out.tin.vertices[t.v[0]], &b = out.tin.vertices[t.v[1]],
                      &c = out.tin.vertices[t.v[2]];
      if (inside.Locate({(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3}) == PointInPolygon::kOutside)
        continue;
      if (row.tag) {
        TB_ASSIGN_OR_RETURN(t.tag, index.Tag(*row.tag));
      }
      out.tin.triangles.push_back(t);
      out.triangle_ids.push_back(id);
    }
  }
  return out;
}

// `out` with only the vertices its triangles use, its neighbours linked; Corruption naming
// `feature` when the triangles overlap.
Result<LoadedSurface> WithUsedVertices(LoadedSurface out, int64_t feature) {
  std::vector<int64_t> remap(out.tin.vertices.size(), -1);
  Tin compact;
  compact.tags = out.tin.tags;
  std::vector<int64_t> ids;
  for (TinTriangle t : out.tin.triangles) {
    for (uint32_t& v : t.v) {
      if (remap[v] < 0) {
        remap[v] = static_cast<int64_t>(compact.vertices.size());
        compact.vertices.push_back(out.tin.vertices[v]);
        ids.push_back(out.vertex_ids[v]);
      }
      v = static_cast<uint32_t>(remap[v]);
    }
    compact.triangles.push_back(t);
  }
  if (!LinkNeighbours(compact))
    return Status::Corruption("feature " + std::to_string(feature) + ": its triangles overlap");
  out.tin = std::move(compact);
  out.vertex_ids = std::move(ids);
  return out;
}

}  // namespace

Result<LoadedSurface> LoadFeatureSurface(Store& store, int64_t feature) {
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  TB_ASSIGN_OR_RETURN(const int64_t surface_id, SurfaceIdOfFeature(store, feature));
  SurfaceStore surfaces(store);
  TB_ASSIGN_OR_RETURN(SurfaceInfo surface, surfaces.FindById(surface_id));
  TB_ASSIGN_OR_RETURN(EditorFeature f, LoadFeature(store, surface, feature));
  if (!IsPolygonMode(f.mode))
    return Status::InvalidArgument("feature " + std::to_string(feature) + " is a " +
                                   FeatureModeName(f.mode) + ": it has no inside to export");
  MeshTables tables(store.db(), surface);
  TB_ASSIGN_OR_RETURN(LoadedSurface read,
                      TrianglesInside(tables, surface.blocks, BoxOf(f), *InsideOf(f)));
  // Vertices of triangles left outside were read too; keep only the used ones.
  return WithUsedVertices(std::move(read), feature);
}

LineElevation LineElevationOf(const std::vector<EditorFeature>& features, double near) {
  std::vector<Line3> lines;
  for (const EditorFeature& f : features) {
    if (!IsLineMode(f.mode) || f.z_from != ZFrom::kFeature) continue;
    for (size_t k = 0; k < f.lines.size() && k < f.line_z.size(); ++k)
      lines.push_back({f.id, f.lines[k], f.line_z[k]});
  }
  return LineElevation(std::move(lines), near);
}

std::vector<Polygon> ReplacePolygons(const std::vector<EditorFeature>& features) {
  std::vector<Polygon> out;
  for (const EditorFeature& f : features)
    if (f.mode == FeatureMode::kReplace)
      out.insert(out.end(), f.polygons.begin(), f.polygons.end());
  return out;
}

}  // namespace tinbase
