#include "db/feature_store.h"

#include <map>

#include "core/tin/tin_raster.h"
#include "core/vector/feature_wkb.h"

namespace tinbase {

namespace {

Result<std::vector<EditorFeature>> SelectFeatures(Store& store, const SurfaceInfo& surface,
                                                  std::optional<int64_t> only) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("SELECT f.id, f.name, f.mode, f.level, t.value, "
                                        "f.geometry, f.attributes FROM features f LEFT JOIN tags t "
                                        "ON t.id = f.tag WHERE f.surface = ?1 "
                                        "AND (?2 IS NULL OR f.id = ?2) ORDER BY f.id"));
  stmt->Bind(1, surface.id);
  if (only) stmt->Bind(2, *only); else stmt->BindNull(2);
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
    f.mode = stmt->ColumnText(2);
    if (!stmt->ColumnIsNull(3)) f.level = stmt->ColumnDouble(3);
    if (!stmt->ColumnIsNull(4)) f.tag = stmt->ColumnText(4);
    f.attributes = nlohmann::json::parse(stmt->ColumnText(6), nullptr, /*allow_exceptions=*/false);
    if (f.attributes.is_discarded()) f.attributes = nlohmann::json::object();
    size_t size = 0;
    const uint8_t* blob = stmt->ColumnBlob(5, &size);
    std::vector<uint8_t> wkb(blob, blob + size);
    if (IsBreakline(f.mode)) {
      auto lines = LinesFromWkb(wkb);
      if (!lines.ok()) {
        status = lines.status().WithContext(f.label);
        break;
      }
      f.lines = std::move(*lines);
    } else {
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
  TB_ASSIGN_OR_RETURN(Statement * insert,
                      store.db().Cached("INSERT OR IGNORE INTO tags(value) VALUES (?)"));
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
  Box box;
  for (const Polygon& p : f.polygons)
    for (const Point2& q : p.shell) box.Add(q);
  for (const auto& line : f.lines)
    for (const Point2& q : line) box.Add(q);
  return box;
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
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("INSERT INTO features(surface, name, mode, level, tag, "
                                        "attributes, geometry, min_x, min_y, max_x, max_y, tx) "
                                        "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)"));
  std::optional<int64_t> tag_id;
  if (f.tag) {
    TB_ASSIGN_OR_RETURN(tag_id, InternTag(store, *f.tag));
  }
  const std::vector<uint8_t> wkb =
      IsBreakline(f.mode) ? LinesToWkb(f.lines) : PolygonsToWkb(f.polygons);
  const Box box = BoxOf(f);
  stmt->Bind(1, surface.id).Bind(2, f.tag.value_or(f.label)).Bind(3, f.mode);
  if (f.level) stmt->Bind(4, *f.level); else stmt->BindNull(4);
  if (tag_id) stmt->Bind(5, *tag_id); else stmt->BindNull(5);
  stmt->Bind(6, f.attributes.dump()).BindBlob(7, wkb.data(), wkb.size());
  stmt->Bind(8, box.min_x).Bind(9, box.min_y).Bind(10, box.max_x).Bind(11, box.max_y).Bind(12, tx);
  TB_RETURN_IF_ERROR(stmt->Run());
  f.id = store.db().LastInsertRowId();
  return Status::Ok();
}

Status DeleteFeature(Store& store, int64_t id) {
  TB_ASSIGN_OR_RETURN(Statement * constraints,
                      store.db().Cached("DELETE FROM constraints WHERE feature = ?"));
  constraints->Bind(1, id);
  TB_RETURN_IF_ERROR(constraints->Run());
  TB_ASSIGN_OR_RETURN(Statement * feature, store.db().Cached("DELETE FROM features WHERE id = ?"));
  feature->Bind(1, id);
  return feature->Run();
}

Paint PaintFromFeatures(const std::vector<EditorFeature>& features, const Grid* dem, Tin& tin) {
  tin.tags.clear();
  std::map<std::string, int32_t> tag_index;
  std::vector<PaintedFeature> painted;
  for (const EditorFeature& f : features) {
    if (IsBreakline(f.mode)) continue;
    auto mode = ParsePaintMode(f.mode);
    if (!mode.ok()) continue;  // the schema's CHECK allows only the known modes
    PaintedFeature p;
    p.polygons = f.polygons;
    p.mode = *mode;
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

std::vector<Polygon> ReplacePolygons(const std::vector<EditorFeature>& features) {
  std::vector<Polygon> out;
  for (const EditorFeature& f : features)
    if (f.mode == "replace") out.insert(out.end(), f.polygons.begin(), f.polygons.end());
  return out;
}

}  // namespace tinbase
