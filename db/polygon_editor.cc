#include "db/polygon_editor.h"

#include <cmath>
#include <limits>
#include <map>

#include "core/tin/constrained_rebuild.h"
#include "core/tin/drape.h"
#include "core/geometry/polygon_locator.h"
#include "core/tin/feature_paint.h"
#include "core/tin/tolerance_refiner.h"
#include "core/vector/feature_wkb.h"
#include "core/vector/polygon_source.h"
#include "db/change_log.h"
#include "db/dem_store.h"
#include "db/feature_store.h"
#include "db/point_locator.h"
#include "db/surface_store.h"

namespace tinbase {

namespace {

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

// Replace levels go into the vertices first, so refinement approximates the DEM with the
// surface as it will be (a flattened ring pulls the triangles outside it down or up).
Tin RefineToDem(Tin tin, const std::vector<EditorFeature>& features, const Grid& dem,
                double tolerance, const ElevationFn& elevation) {
  const Paint levels = PaintFromFeatures(features, nullptr, tin);
  ApplyPaint(levels, tin, /*apply_levels=*/true);
  Cdt cdt;
  cdt.InsertVertices(tin.vertices);
  for (const auto& [a, b] : tin.constraints) cdt.InsertConstraint(a, b);
  const PolygonLocator replaced(ReplacePolygons(features));
  RefineOptions options;
  options.tolerance = tolerance;
  if (!replaced.empty())
    options.excluded = [&](double x, double y) {
      return replaced.Locate({x, y}) != PointInPolygon::kOutside;
    };
  RefineToTolerance(cdt, dem, options);
  Tin refined = cdt.ToTin(elevation);
  ApplyPaint(PaintFromFeatures(features, &dem, refined), refined, /*apply_levels=*/true);
  return refined;
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
  TB_ASSIGN_OR_RETURN(Tin constrained, InsertConstraints(base.tin, lines, elevation));
  TB_ASSIGN_OR_RETURN(Grid grid, dems.ReadGrid(dem));

  PolygonAddReport report;
  Change change;
  change.surface = surface.id;
  change.action = "polygon add";
  change.removed = static_cast<int64_t>(base.tin.triangles.size());
  Box box;
  for (const EditorFeature& f : added) box.Add(BoxOf(f));
  change.min_x = box.min_x, change.min_y = box.min_y, change.max_x = box.max_x, change.max_y = box.max_y;
  features.insert(features.end(), added.begin(), added.end());
  const Tin tin = RefineToDem(std::move(constrained), features, grid, drape.tolerance, elevation);
  change.added = static_cast<int64_t>(tin.triangles.size());
  TB_ASSIGN_OR_RETURN(report.tx, AppendChange(store, change));
  for (EditorFeature& f : added) TB_RETURN_IF_ERROR(WriteFeature(store, surface, report.tx, f));
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
