#include "db/polygon_editor.h"

#include <cmath>
#include <limits>
#include <map>

#include "core/tin/constrained_rebuild.h"
#include "core/tin/drape.h"
#include "core/tin/feature_paint.h"
#include "core/vector/feature_wkb.h"
#include "core/vector/polygon_source.h"
#include "db/change_log.h"
#include "db/dem_store.h"
#include "db/point_locator.h"
#include "db/surface_store.h"

namespace tinbase {

namespace {

// A feature as the editor handles it, read from a file or from the store.
struct EditorFeature {
  int64_t id = 0;  // store id; 0 until written
  std::string label;
  std::string mode;
  std::optional<std::string> tag;
  std::optional<double> level;
  nlohmann::json attributes = nlohmann::json::object();
  std::vector<Polygon> polygons;
  std::vector<std::vector<Point2>> lines;
};

bool IsBreakline(const std::string& mode) { return mode == "breakline"; }

Status CheckModeOptions(const PolygonAddOptions& o) {
  if (!IsBreakline(o.mode)) TB_RETURN_IF_ERROR(ParsePaintMode(o.mode).status());
  if (o.mode == "replace" && !o.level)
    return Status::InvalidArgument("mode replace needs --level (the flat z)");
  if (o.level && !std::isfinite(*o.level))
    return Status::InvalidArgument("--level must be a finite number");
  if (!o.tag.empty() && !o.tag_field.empty())
    return Status::InvalidArgument("give --tag or --tag-field, not both");
  return Status::Ok();
}

Result<std::vector<EditorFeature>> ReadFeatures(const PolygonAddOptions& o, const Crs& crs) {
  VectorSourceOptions source;
  source.layer = o.layer;
  source.where = o.where;
  source.tag_field = o.tag_field;
  source.target_crs = crs;
  std::vector<EditorFeature> out;
  const auto base = [&](EditorFeature& f, const std::string& label, const nlohmann::json& attrs,
                        const std::optional<std::string>& tag) {
    f.label = label;
    f.mode = o.mode;
    f.attributes = attrs;
    f.tag = o.tag.empty() ? tag : std::optional<std::string>(o.tag);
    f.level = o.level;
  };
  if (IsBreakline(o.mode)) {
    TB_ASSIGN_OR_RETURN(auto lines, ReadLineFeatures(o.file, source));
    for (auto& line : lines) {
      EditorFeature f;
      base(f, line.label, line.attributes, line.tag);
      f.lines = std::move(line.lines);
      out.push_back(std::move(f));
    }
  } else {
    TB_ASSIGN_OR_RETURN(auto polygons, ReadPolygonFeatures(o.file, source));
    for (auto& polygon : polygons) {
      EditorFeature f;
      base(f, polygon.label, polygon.attributes, polygon.tag);
      f.polygons = std::move(polygon.polygons);
      out.push_back(std::move(f));
    }
  }
  return out;
}

// Every ring and line of `f`, draped and densified, each vertex checked to lie on the surface.
Status DrapeFeature(Store& store, const SurfaceInfo& surface, const EditorFeature& f,
                    const ElevationFn& elevation, const DrapeOptions& base,
                    std::vector<ConstraintPolyline>* out) {
  const auto add = [&](const std::vector<Point2>& points, bool closed,
                       const std::string& where) -> Status {
    DrapeOptions options = base;
    options.closed = closed;
    auto draped = DrapePolyline(points, elevation, options);
    if (!draped.ok()) return draped.status().WithContext(f.label + ", " + where);
    for (size_t i = 0; i < draped->size(); ++i) {
      const TinVertex& v = (*draped)[i];
      auto located = LocatePoint(store, surface, v.x, v.y);
      if (!located.ok())
        return Status::InvalidArgument(f.label + ", " + where + ": " + FormatPoint({v.x, v.y}) +
                                       " lies outside surface '" + surface.name + "'");
    }
    out->push_back({std::move(*draped), closed});
    return Status::Ok();
  };
  for (size_t p = 0; p < f.polygons.size(); ++p) {
    const std::string part = f.polygons.size() > 1 ? "polygon " + std::to_string(p) + ", " : "";
    TB_RETURN_IF_ERROR(add(f.polygons[p].shell, true, part + "ring 0"));
    for (size_t h = 0; h < f.polygons[p].holes.size(); ++h)
      TB_RETURN_IF_ERROR(add(f.polygons[p].holes[h], true, part + "ring " + std::to_string(h + 1)));
  }
  for (size_t l = 0; l < f.lines.size(); ++l)
    TB_RETURN_IF_ERROR(add(f.lines[l], false, "line " + std::to_string(l)));
  return Status::Ok();
}

Result<std::vector<EditorFeature>> LoadFeatures(Store& store, const SurfaceInfo& surface) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("SELECT f.id, f.name, f.mode, f.level, t.value, "
                                        "f.geometry FROM features f LEFT JOIN tags t "
                                        "ON t.id = f.tag WHERE f.surface = ? ORDER BY f.id"));
  stmt->Bind(1, surface.id);
  std::vector<EditorFeature> out;
  while (true) {
    TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
    if (!row) break;
    EditorFeature f;
    f.id = stmt->ColumnInt(0);
    f.label = "feature " + std::to_string(f.id);
    f.mode = stmt->ColumnText(2);
    if (!stmt->ColumnIsNull(3)) f.level = stmt->ColumnDouble(3);
    if (!stmt->ColumnIsNull(4)) f.tag = stmt->ColumnText(4);
    size_t size = 0;
    const uint8_t* blob = stmt->ColumnBlob(5, &size);
    std::vector<uint8_t> wkb(blob, blob + size);
    if (IsBreakline(f.mode)) {
      TB_ASSIGN_OR_RETURN(f.lines, LinesFromWkb(wkb));
    } else {
      TB_ASSIGN_OR_RETURN(f.polygons, PolygonsFromWkb(wkb));
    }
    out.push_back(std::move(f));
  }
  stmt->Reset();
  return out;
}

// Visibility and tags from scratch: the features' paint, and no triangle visible over nodata.
void RepaintSurface(const std::vector<EditorFeature>& features, const ElevationFn& elevation,
                    Tin& tin) {
  tin.tags.clear();
  std::map<std::string, int32_t> tag_index;
  std::vector<PaintedFeature> painted;
  for (const EditorFeature& f : features) {
    if (IsBreakline(f.mode)) continue;
    PaintedFeature p;
    p.polygons = f.polygons;
    p.mode = *ParsePaintMode(f.mode);
    p.level = f.level.value_or(0);
    if (f.tag) {
      auto [it, added] = tag_index.emplace(*f.tag, static_cast<int32_t>(tin.tags.size()));
      if (added) tin.tags.push_back(*f.tag);
      p.tag = it->second;
    }
    painted.push_back(std::move(p));
  }
  ApplyPaint(ComputePaint(tin, painted), tin, /*apply_levels=*/true);
  for (TinTriangle& t : tin.triangles) {
    const TinVertex& a = tin.vertices[t.v[0]];
    const TinVertex& b = tin.vertices[t.v[1]];
    const TinVertex& c = tin.vertices[t.v[2]];
    if (!std::isfinite(elevation((a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3))) t.visible = false;
  }
}

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

struct Box {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -std::numeric_limits<double>::infinity(), max_y = max_x;
  void Add(const Point2& p) {
    min_x = std::min(min_x, p.x), min_y = std::min(min_y, p.y);
    max_x = std::max(max_x, p.x), max_y = std::max(max_y, p.y);
  }
  void Add(const Box& b) { Add(Point2{b.min_x, b.min_y}), Add(Point2{b.max_x, b.max_y}); }
};

Box BoxOf(const EditorFeature& f) {
  Box box;
  for (const Polygon& p : f.polygons)
    for (const Point2& q : p.shell) box.Add(q);
  for (const auto& line : f.lines)
    for (const Point2& q : line) box.Add(q);
  return box;
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

}  // namespace

Result<PolygonAddReport> AddPolygons(Store& store, const PolygonAddOptions& options) {
  TB_RETURN_IF_ERROR(CheckModeOptions(options));
  SurfaceStore surfaces(store);
  TB_ASSIGN_OR_RETURN(SurfaceInfo surface, surfaces.Find(options.surface));
  if (!surface.dem)
    return Status::InvalidArgument("surface '" + surface.name + "' is not draped on a DEM");
  TB_ASSIGN_OR_RETURN(auto crs, store.GetCrs());
  if (!crs) return Status::InvalidArgument("the store has no CRS yet: import a DEM first");
  DemStore dems(store);
  TB_ASSIGN_OR_RETURN(DemInfo dem, dems.FindById(*surface.dem));
  const ElevationFn elevation = [&](double x, double y) {
    auto z = dems.Sample(dem, x, y);
    return z.ok() ? *z : std::numeric_limits<double>::quiet_NaN();
  };

  TB_ASSIGN_OR_RETURN(std::vector<EditorFeature> added, ReadFeatures(options, *crs));
  DrapeOptions drape;
  drape.tolerance = surface.tolerance.value_or(1.0);
  drape.min_spacing = std::min(dem.geometry.cell_x, -dem.geometry.cell_y);
  std::vector<ConstraintPolyline> lines;
  for (const EditorFeature& f : added)
    TB_RETURN_IF_ERROR(DrapeFeature(store, surface, f, elevation, drape, &lines));

  TB_ASSIGN_OR_RETURN(auto tx, store.BeginWrite());
  TB_ASSIGN_OR_RETURN(LoadedSurface base, surfaces.Load(surface));
  TB_ASSIGN_OR_RETURN(std::vector<EditorFeature> features, LoadFeatures(store, surface));
  TB_ASSIGN_OR_RETURN(Tin tin, InsertConstraints(base.tin, lines, elevation));

  PolygonAddReport report;
  Change change;
  change.surface = surface.id;
  change.action = "polygon add";
  change.removed = static_cast<int64_t>(base.tin.triangles.size());
  change.added = static_cast<int64_t>(tin.triangles.size());
  Box box;
  for (const EditorFeature& f : added) box.Add(BoxOf(f));
  change.min_x = box.min_x, change.min_y = box.min_y, change.max_x = box.max_x, change.max_y = box.max_y;
  TB_ASSIGN_OR_RETURN(report.tx, AppendChange(store, change));
  for (EditorFeature& f : added) TB_RETURN_IF_ERROR(WriteFeature(store, surface, report.tx, f));
  features.insert(features.end(), added.begin(), added.end());
  RepaintSurface(features, elevation, tin);
  TB_RETURN_IF_ERROR(surfaces.Replace(surface, tin).status());
  TB_RETURN_IF_ERROR(tx->Commit());

  report.features = static_cast<int64_t>(added.size());
  for (const ConstraintPolyline& l : lines) report.ring_vertices += static_cast<int64_t>(l.points.size());
  report.removed = change.removed;
  report.added = change.added;
  for (const TinTriangle& t : tin.triangles) report.visible += t.visible;
  report.first_feature_id = added.empty() ? 0 : added.front().id;
  return report;
}

}  // namespace tinbase
