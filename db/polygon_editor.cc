#include "db/polygon_editor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/tin/drape.h"
#include "core/tin/feature_paint.h"
#include "core/vector/feature_wkb.h"
#include "core/vector/polygon_source.h"
#include "db/change_log.h"
#include "db/dem_store.h"
#include "db/edit/line_z.h"
#include "db/edit/surface_of_feature.h"
#include "db/edit/update_engine_test_hooks.h"
#include "db/edit/write_retry.h"
#include "db/feature_store.h"
#include "db/history/feature_versions.h"
#include "db/history/mesh_image_store.h"
#include "db/mesh/mesh_tables.h"
#include "db/mesh_cache.h"
#include "db/point_locator.h"
#include "db/surface_store.h"

namespace tinbase {

namespace {

// Points features are `tinbase points add`'s: the polygon editor takes the other modes.
Status CheckEditableMode(FeatureMode mode, const std::string& prefix) {
  if (mode != FeatureMode::kPoints) return Status::Ok();
  return Status::InvalidArgument(prefix + "mode points is for `tinbase points add`");
}

// In-memory features may carry their own mode and level, so for them the mode is checked
// feature by feature (FromMemory).
Status CheckModeOptions(const PolygonAddOptions& o) {
  if (!o.mode && !o.features)
    return Status::InvalidArgument(
        "a feature mode is needed (clip, erase, fill, replace, breakline or softline)");
  if (o.mode) TB_RETURN_IF_ERROR(CheckEditableMode(*o.mode, ""));
  if (!o.features && *o.mode == FeatureMode::kReplace && !o.level)
    return Status::InvalidArgument("mode replace needs --level (the flat z)");
  if (o.level && !std::isfinite(*o.level))
    return Status::InvalidArgument("--level must be a finite number");
  if (!o.tag.empty() && !o.tag_field.empty())
    return Status::InvalidArgument("give --tag or --tag-field, not both");
  if (o.z_from == ZFrom::kFeature && o.mode && !IsLineMode(*o.mode))
    return Status::InvalidArgument(
        "--z-from feature is for lines (modes breakline and softline), not mode " +
        std::string(FeatureModeName(*o.mode)));
  return Status::Ok();
}

// The editor's feature for in-memory feature `m`, with the options' mode, tag and level where
// `m` has none. InvalidArgument naming m.label when it has no mode, replace has no finite level,
// or the geometry does not suit the mode (lines for breaklines, polygons for the others).
Result<EditorFeature> FromMemory(const MemoryFeature& m, const PolygonAddOptions& o) {
  EditorFeature f;
  f.label = m.label;
  if (!m.mode && !o.mode)
    return Status::InvalidArgument(
        m.label + ": a feature mode is needed (clip, erase, fill, replace, breakline or softline)");
  f.mode = m.mode ? *m.mode : *o.mode;
  f.tag = m.tag ? m.tag : (o.tag.empty() ? std::nullopt : std::optional<std::string>(o.tag));
  f.level = m.level ? m.level : o.level;
  if (f.mode == FeatureMode::kReplace && !f.level)
    return Status::InvalidArgument(m.label + ": mode replace needs a level (the flat z)");
  if (f.level && !std::isfinite(*f.level))
    return Status::InvalidArgument(m.label + ": the level must be a finite number");
  TB_RETURN_IF_ERROR(CheckEditableMode(f.mode, m.label + ": "));
  const bool breakline = IsLineMode(f.mode);
  if (breakline ? m.lines.empty() : m.polygons.empty())
    return Status::InvalidArgument(m.label + ": mode " + std::string(FeatureModeName(f.mode)) +
                                   (breakline ? " needs a LineString or MultiLineString"
                                              : " needs a Polygon or MultiPolygon"));
  f.attributes = m.attributes;
  f.polygons = breakline ? std::vector<Polygon>{} : m.polygons;
  f.lines = breakline ? m.lines : std::vector<std::vector<Point2>>{};
  if (m.z_from.value_or(o.z_from) == ZFrom::kFeature) {
    if (!breakline)
      return Status::InvalidArgument(m.label + ": z from the feature is for lines, not mode " +
                                     FeatureModeName(f.mode));
    f.z_from = ZFrom::kFeature;
    f.line_z = m.line_z;
  }
  return f;
}

// With `rejected`, invalid features are listed there and skipped (see VectorSourceOptions).
Result<std::vector<EditorFeature>> ReadFeatures(const PolygonAddOptions& o, const Crs& crs,
                                                std::vector<std::string>* rejected = nullptr) {
  if (o.features) {
    std::vector<EditorFeature> out;
    for (const MemoryFeature& m : *o.features) {
      TB_ASSIGN_OR_RETURN(EditorFeature f, FromMemory(m, o));
      out.push_back(std::move(f));
    }
    return out;
  }
  VectorSourceOptions source;
  source.rejected = rejected;
  source.layer = o.layer;
  source.where = o.where;
  source.tag_field = o.tag_field;
  source.target_crs = crs;
  source.repair = o.repair;
  std::vector<EditorFeature> out;
  const auto base = [&](EditorFeature& f, const std::string& label, const nlohmann::json& attrs,
                        const std::optional<std::string>& tag) {
    f.label = label;
    f.mode = *o.mode;
    f.attributes = attrs;
    f.tag = o.tag.empty() ? tag : std::optional<std::string>(o.tag);
    f.level = o.level;
  };
  if (IsLineMode(*o.mode)) {
    TB_ASSIGN_OR_RETURN(auto lines, ReadLineFeatures(o.file, source));
    for (auto& line : lines) {
      EditorFeature f;
      base(f, line.label, line.attributes, line.tag);
      if (o.z_from == ZFrom::kFeature && !line.has_z)
        return Status::InvalidArgument(line.label +
                                       ": --z-from feature needs lines with z (LineString Z)");
      f.lines = std::move(line.lines);
      if (o.z_from == ZFrom::kFeature) {
        f.z_from = ZFrom::kFeature;
        f.line_z = std::move(line.z);
      }
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

// InvalidArgument naming the first vertex of `points` (ring or line `where` of `f`) that lies
// outside the surface; Ok when none does.
Status CheckOnSurface(Store& store, const SurfaceInfo& surface, const EditorFeature& f,
                      const std::vector<Point2>& points, const std::string& where) {
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  PointLocator locator(store, surface);
  for (size_t i = 0; i < points.size(); ++i) {
    auto located = locator.LocateTriangle(points[i].x, points[i].y);
    if (located.ok()) continue;
    if (located.status().code() != StatusCode::kNotFound) return located.status();
    return Status::InvalidArgument(f.label + ", " + where + ", vertex " + std::to_string(i) + ": " +
                                   FormatPoint(points[i]) + " lies outside surface '" +
                                   surface.name + "'");
  }
  return Status::Ok();
}

// Calls `check(points, closed, where)` for every ring and line of `f` in order, until one fails.
template <typename Check>
Status ForEachPolyline(const EditorFeature& f, const Check& check) {
  for (size_t p = 0; p < f.polygons.size(); ++p) {
    const std::string part = f.polygons.size() > 1 ? "polygon " + std::to_string(p) + ", " : "";
    TB_RETURN_IF_ERROR(check(f.polygons[p].shell, true, part + "ring 0"));
    for (size_t h = 0; h < f.polygons[p].holes.size(); ++h)
      TB_RETURN_IF_ERROR(
          check(f.polygons[p].holes[h], true, part + "ring " + std::to_string(h + 1)));
  }
  for (size_t l = 0; l < f.lines.size(); ++l)
    TB_RETURN_IF_ERROR(check(f.lines[l], false, "line " + std::to_string(l)));
  return Status::Ok();
}

// The first input vertex of `f` outside the surface, as CheckOnSurface.
Status FeatureOnSurface(Store& store, const SurfaceInfo& surface, const EditorFeature& f) {
  return ForEachPolyline(f, [&](const std::vector<Point2>& points, bool, const std::string& where) {
    return CheckOnSurface(store, surface, f, points, where);
  });
}

// Every ring and line of `f`, draped and densified. Whether the input vertices lie on the
// surface is checked only when something fails (here or in the edit: the engine locates every
// point and refuses any outside), so that the message can name the input vertex: locating every
// vertex up front would walk the mesh once more for every vertex of every feature.
Status DrapeFeature(Store& store, const SurfaceInfo& surface, const EditorFeature& f,
                    const DrapeElevationFn& elevation, const DrapeOptions& base,
                    std::vector<EditPolyline>* out) {
  return ForEachPolyline(
      f, [&](const std::vector<Point2>& points, bool closed, const std::string& where) -> Status {
        DrapeOptions options = base;
        options.closed = closed;
        auto draped = DrapePolyline(points, elevation, options);
        // A DEM block that cannot be read is the store's fault, not the feature's: its error
        // goes out as it is, before anything that would blame the input vertices.
        if (!draped.ok() && draped.status().code() != StatusCode::kInvalidArgument)
          return draped.status().WithContext(f.label + ", " + where);
        if (!draped.ok()) {
          TB_RETURN_IF_ERROR(CheckOnSurface(store, surface, f, points, where));
          return draped.status().WithContext(f.label + ", " + where);
        }
        out->push_back({std::move(*draped), closed, 0});
        return Status::Ok();
      });
}

// What every edit of one surface needs: the surface, its DEM and the draping rules.
struct SurfaceSession {
  explicit SurfaceSession(Store& s) : store(s), dems(s), mesh(s, surface) {}
  Store& store;
  SurfaceInfo surface;
  DemStore dems;
  DemInfo dem;
  std::optional<Crs> crs;
  DrapeOptions drape;
  DrapeElevationFn elevation;  // NaN where the DEM has no data; an error where a read failed
  // The surface's features as they are after change `features_tx`: a load feature by feature
  // (`--each`) hands them from one transaction to the next instead of reading and parsing them
  // all again for every feature. Valid only while no other change came between (change numbers
  // are consecutive); -1 when not known.
  std::vector<EditorFeature> features;
  int64_t features_tx = -1;
  // The surface's mesh rows the edits read, kept across the transactions of a load feature by
  // feature under the same rule (db/mesh_cache.h checks it), dropped after any failure.
  MeshCache mesh;
  // The ring points of every feature of a load feature by feature (LocalEdit::load_points).
  size_t load_points = 0;
  // The lowest and highest z of the DEM's cells, read when a level is first checked.
  std::optional<std::pair<double, double>> relief;
  bool strict = false;  // PolygonAddOptions::strict: no clipping to the data area
  // The rectangle the surface covers (SurfaceHull), found when the first polygon feature is
  // clipped: edits keep it (they stay inside the surface).
  std::optional<PlanRect> hull;
  BeforeCommit before_commit;  // the caller's, run inside each edit's transaction
  // The edits run inside a write transaction the caller opened and commits (ApplyFeatureEdit).
  bool in_caller_transaction = false;
};

Result<std::unique_ptr<SurfaceSession>> OpenSession(Store& store, const SurfaceInfo& surface) {
  auto session = std::make_unique<SurfaceSession>(store);
  session->surface = surface;
  if (!surface.dem)
    return Status::InvalidArgument("surface '" + surface.name + "' is not draped on a DEM");
  TB_ASSIGN_OR_RETURN(session->crs, store.GetCrs());
  if (!session->crs) return Status::InvalidArgument("the store has no CRS yet: import a DEM first");
  TB_ASSIGN_OR_RETURN(session->dem, session->dems.FindById(*surface.dem));
  session->drape.tolerance = surface.tolerance.value_or(1.0);
  session->drape.min_spacing =
      std::min(session->dem.geometry.cell_x, std::fabs(session->dem.geometry.cell_y));
  SurfaceSession* s = session.get();
  session->elevation = [s](double x, double y) { return s->dems.Elevation(s->dem, x, y); };
  return session;
}

// The vertices of a feature's rings and lines, as read (draping adds some).
size_t RingPoints(const EditorFeature& f) {
  size_t points = 0;
  for (const Polygon& polygon : f.polygons) {
    points += polygon.shell.size();
    for (const auto& hole : polygon.holes) points += hole.size();
  }
  for (const auto& line : f.lines) points += line.size();
  return points;
}

// LocalEdit::load_points for a load of `features` feature by feature: their ring points when
// they are at least a quarter as many as the surface's triangles and the session's cache can keep
// the surface as the load adds triangles (at most half its limit), else 0. Decided once for the
// load: counting the triangles is a scan of the surface's rows, too slow to repeat in every edit.
Result<size_t> LoadPointsThatReadTheSurface(Store& store, const SurfaceInfo& surface,
                                            const std::vector<EditorFeature>& features) {
  size_t points = 0;
  for (const EditorFeature& f : features) points += RingPoints(f);
  if (points < kMinWholeSurfaceRegion) return size_t{0};
  TB_ASSIGN_OR_RETURN(const int64_t triangles, MeshTables(store.db(), surface).CountTriangles());
  const bool reaches = static_cast<int64_t>(points) * 4 >= triangles;
  const bool kept = triangles * 2 <= static_cast<int64_t>(MeshCache::kMaxKeptTriangles);
  return reaches && kept ? points : size_t{0};
}

// A feature to add with its draped polylines.
struct NewFeature {
  EditorFeature feature;
  std::vector<EditPolyline> lines;
  ClipVerdict verdict = ClipVerdict::kInside;  // of OverhangClip; kOutside: nothing to add
  double area_outside = 0;
};

// The range a replace level may take: the DEM's relief widened by ten times its height, and by
// at least kLevelMargin. A level beyond it is a typing or unit mistake (1e100, a level in
// millimetres); the flat region it makes would also be steeper than any check can follow.
constexpr double kLevelMargin = 10000;

std::string FormatNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", v);
  return text;
}

Result<std::pair<double, double>> LevelRange(SurfaceSession& session) {
  if (!session.relief) {
    TB_ASSIGN_OR_RETURN(session.relief, session.dems.Relief(session.dem));
  }
  const auto [low, high] = *session.relief;
  const double margin = std::max(10 * (high - low), kLevelMargin);
  return std::pair{low - margin, high + margin};
}

Status CheckLevel(SurfaceSession& session, const EditorFeature& f) {
  if (!f.level) return Status::Ok();
  TB_ASSIGN_OR_RETURN(auto range, LevelRange(session));
  if (*f.level >= range.first && *f.level <= range.second) return Status::Ok();
  return Status::InvalidArgument(f.label + ": level " + FormatNumber(*f.level) +
                                 " is far outside the relief of surface '" + session.surface.name +
                                 "' (levels from " + FormatNumber(range.first) + " to " +
                                 FormatNumber(range.second) + " are accepted)");
}

// The feature checked, cut to the data area (unless strict) and draped; a feature wholly outside
// comes back undraped with verdict kOutside.
Result<NewFeature> Prepare(SurfaceSession& session, EditorFeature f) {
  TB_RETURN_IF_ERROR(CheckLevel(session, f));
  NewFeature out;
  if (!session.strict) {
    if (!session.hull && !f.polygons.empty()) {
      TB_ASSIGN_OR_RETURN(session.hull, SurfaceHull(session.store, session.surface, session.dem));
    }
    TB_ASSIGN_OR_RETURN(
        DataAreaClip clip,
        ClipFeatureToDataArea(session.dems, session.dem, session.hull.value_or(PlanRect{}), f));
    out.verdict = clip.verdict;
    out.area_outside = clip.area_outside;
    if (clip.verdict == ClipVerdict::kOutside) {
      out.feature = std::move(f);
      return out;
    }
  }
  if (f.z_from == ZFrom::kFeature) {
    TB_ASSIGN_OR_RETURN(out.lines, OwnZPolylines(f));
  } else {
    TB_RETURN_IF_ERROR(DrapeFeature(session.store, session.surface, f, session.elevation,
                                    session.drape, &out.lines));
  }
  out.feature = std::move(f);
  return out;
}

// InvalidArgument "<label>: lies wholly outside ..." for a feature of verdict kOutside.
Status RefuseOutside(const SurfaceSession& session, const NewFeature& n) {
  if (n.verdict != ClipVerdict::kOutside) return Status::Ok();
  return Status::InvalidArgument(n.feature.label + ": " +
                                 WhollyOutsideMessage(session.surface.name));
}

// The surface's features before the edit of change `tx`: the session's when they are those of
// the change just before, else read from the store.
Result<std::vector<EditorFeature>> FeaturesBefore(SurfaceSession& session, int64_t tx) {
  std::vector<EditorFeature> existing;
  if (session.features_tx >= 0 && tx == session.features_tx + 1) {
    existing = std::move(session.features);
  } else {
    TB_ASSIGN_OR_RETURN(existing, LoadFeatures(session.store, session.surface));
  }
  return existing;
}

// The local edit that takes the `removed` features out of `existing` (the surface's features),
// before the `added` ones go in: the kept features, and where paint may change.
LocalEdit EditRemoving(const SurfaceSession& session, const std::vector<NewFeature>& added,
                       const std::vector<int64_t>& removed, std::vector<EditorFeature> existing) {
  // Clip polygons act as one union over the whole surface: adding or removing one can hide or
  // show triangles anywhere, so the paint area is then the whole DEM.
  const auto is_clip = [](const EditorFeature& f) { return f.mode == FeatureMode::kClip; };
  bool clip = std::any_of(added.begin(), added.end(),
                          [&](const NewFeature& n) { return is_clip(n.feature); });
  for (const EditorFeature& f : existing)
    clip |= is_clip(f) && std::find(removed.begin(), removed.end(), f.id) != removed.end();
  LocalEdit edit;
  edit.remove = removed;
  edit.load_points = session.load_points;
  if (clip) {
    const GridGeometry& g = session.dem.geometry;
    edit.changed.Add(Point2{g.MinX(), g.MinY()});
    edit.changed.Add(Point2{g.MaxX(), g.MaxY()});
  }
  // The kept features go over whole: moving them one by one made a load of a thousand features
  // feature by feature quadratic.
  const auto is_removed = [&](const EditorFeature& f) {
    return std::find(removed.begin(), removed.end(), f.id) != removed.end();
  };
  for (const EditorFeature& f : existing)
    if (is_removed(f)) edit.changed.Add(BoxOf(f));
  std::erase_if(existing, is_removed);
  edit.features = std::move(existing);
  return edit;
}

// Writes the rows of the `added` features in change `tx` (setting their ids) and moves their
// lines into `edit`; returns the number of line vertices.
Result<int64_t> AddFeatures(SurfaceSession& session, int64_t tx, std::vector<NewFeature>& added,
                            LocalEdit& edit) {
  int64_t ring_vertices = 0;
  for (NewFeature& n : added) {
    const int64_t wanted_id = n.feature.id;  // set when a revert puts a feature back
    TB_RETURN_IF_ERROR(WriteFeature(session.store, session.surface, tx, n.feature));
    TB_RETURN_IF_ERROR(SettleFeatureId(session.store, wanted_id, n.feature));
    for (EditPolyline& line : n.lines) {
      line.feature = n.feature.id;
      ring_vertices += static_cast<int64_t>(line.points.size());
      edit.add.push_back(std::move(line));
    }
    edit.changed.Add(BoxOf(n.feature));
    edit.features.push_back(n.feature);
  }
  // A revert puts features back under their old ids, and paint applies in id order.
  const auto by_id = [](const EditorFeature& a, const EditorFeature& b) { return a.id < b.id; };
  if (!std::is_sorted(edit.features.begin(), edit.features.end(), by_id))
    std::stable_sort(edit.features.begin(), edit.features.end(), by_id);
  return ring_vertices;
}

// Completes the `changes` row of `tx`: the first feature added (else removed), the triangle
// counts of `result`, and the extent of `changed` and the region.
Status RecordChange(Store& store, int64_t tx, const std::vector<NewFeature>& added,
                    const std::vector<int64_t>& removed, const EditResult& result,
                    const Box& changed) {
  Box box = changed;
  box.Add(result.region);
  TB_ASSIGN_OR_RETURN(Statement * update,
                      store.db().Cached("UPDATE changes SET feature = ?, removed = ?, added = ?, "
                                        "min_x = ?, min_y = ?, max_x = ?, max_y = ? WHERE tx = ?"));
  const int64_t feature =
      !added.empty() ? added.front().feature.id : (!removed.empty() ? removed.front() : 0);
  if (feature != 0)
    update->Bind(1, feature);
  else
    update->BindNull(1);
  update->Bind(2, result.removed).Bind(3, result.added);
  update->Bind(4, box.min_x).Bind(5, box.min_y).Bind(6, box.max_x).Bind(7, box.max_y);
  return update->Bind(8, tx).Run();
}

// One transaction: the new features' rows, the engine's local edit (their constraints in, the
// removed features' constraints out), the removed features' rows gone, one `changes` row. The
// lines of `added` are moved into the edit; their features stay.
Result<PolygonAddReport> ApplyEditOnce(SurfaceSession& session, std::vector<NewFeature>& added,
                                       const std::vector<int64_t>& removed,
                                       const std::string& action) {
  Store& store = session.store;
  std::unique_ptr<WriteTransaction> tx;
  if (!session.in_caller_transaction) {
    TB_ASSIGN_OR_RETURN(tx, store.BeginRegionWrite());
  }
  Change change;
  change.surface = session.surface.id;
  change.action = action;
  PolygonAddReport report;
  TB_ASSIGN_OR_RETURN(report.tx, AppendChange(store, change));
  TB_ASSIGN_OR_RETURN(bool mesh_kept, session.mesh.Begin(report.tx));
  report.mesh_kept = mesh_kept ? 1 : 0;
  // With concurrent writers change numbers commit out of order, so a next number does not prove
  // that no other edit came between: the features are kept only with the mesh rows, which the
  // data version guards.
  if (!mesh_kept && store.db().ConcurrentWriters()) session.features_tx = -1;
  if (mesh_kept && TEST_VerifyMesh()) TB_RETURN_IF_ERROR(session.mesh.VerifyAgainstStore());
  TB_ASSIGN_OR_RETURN(std::vector<EditorFeature> existing, FeaturesBefore(session, report.tx));
  session.features_tx = -1;  // until this edit commits

  LocalEdit edit = EditRemoving(session, added, removed, std::move(existing));
  TB_ASSIGN_OR_RETURN(report.ring_vertices, AddFeatures(session, report.tx, added, edit));
  ApplyLineZ(session.dem, edit);
  for (const NewFeature& n : added) report.feature_ids.push_back(n.feature.id);
  TB_RETURN_IF_ERROR(RecordFeatureVersions(store, report.tx, report.feature_ids, removed));
  UpdateEngine engine(store, session.surface, session.dems, session.dem);
  engine.set_mesh_cache(&session.mesh);
  MeshImage image;
  engine.set_mesh_image(&image);
  TB_ASSIGN_OR_RETURN(EditResult result, engine.Apply(edit));
  for (int64_t id : removed) TB_RETURN_IF_ERROR(DeleteFeature(store, id));
  TB_RETURN_IF_ERROR(RecordChange(store, report.tx, added, removed, result, edit.changed));
  TB_RETURN_IF_ERROR(RecordMeshImage(store, report.tx, std::move(image)));
  if (session.before_commit) TB_RETURN_IF_ERROR(session.before_commit(store, report.tx));
  if (tx) TB_RETURN_IF_ERROR(tx->Commit());
  session.features = std::move(edit.features);
  session.features_tx = report.tx;
  session.mesh.Committed(report.tx);

  report.features = static_cast<int64_t>(added.size());
  report.removed = result.removed;
  report.added = result.added;
  report.refinement_points = result.refinement_points;
  report.surface_reads = result.read_whole_surface ? 1 : 0;
  report.first_feature_id = added.empty() ? 0 : added.front().feature.id;
  report.visible = result.visible_added;
  for (const NewFeature& n : added)
    if (n.verdict == ClipVerdict::kCut)
      report.clipped.push_back({n.feature.id, n.feature.label, n.area_outside});
  return report;
}

// ApplyEditOnce, with what a failure needs: the cached rows dropped (the rollback undid what the
// edit wrote, and it may have forgotten only part of it), and an input vertex outside the surface
// named (the engine names only the draped point).
Result<PolygonAddReport> ApplyEdit(SurfaceSession& session, std::vector<NewFeature> added,
                                   const std::vector<int64_t>& removed, const std::string& action) {
  TB_RETURN_IF_ERROR(TEST_FaultStep(0));
  // An edit that lost a race with another writer runs again (db/edit/write_retry.h); each attempt
  // takes a copy of the features, as an attempt moves their lines out.
  const int attempts = session.in_caller_transaction ? 1 : EditAttempts(session.store.db());
  Result<PolygonAddReport> report = Status::Busy("not attempted");
  for (int attempt = 1; attempt <= attempts; ++attempt) {
    if (attempts == 1) {
      report = ApplyEditOnce(session, added, removed, action);
    } else {
      std::vector<NewFeature> copy = added;
      report = ApplyEditOnce(session, copy, removed, action);
    }
    if (report.ok()) return report;
    session.mesh.Clear();
    session.features_tx = -1;
    if (!RetryEdit(report.status(), attempt, attempts)) break;
    PauseBeforeRetry(attempt);
  }
  if (attempts > 1 && report.status().code() == StatusCode::kBusy)
    return GaveUpRetrying(report.status(), attempts);
  if (report.status().code() == StatusCode::kInvalidArgument) {
    for (const NewFeature& n : added)
      TB_RETURN_IF_ERROR(FeatureOnSurface(session.store, session.surface, n.feature));
  }
  return report.status();
}

}  // namespace

Result<PolygonAddReport> AddPolygons(Store& store, const PolygonAddOptions& options) {
  TB_RETURN_IF_ERROR(CheckModeOptions(options));
  TB_ASSIGN_OR_RETURN(SurfaceInfo surface, SurfaceStore(store).Find(options.surface));
  TB_ASSIGN_OR_RETURN(auto session, OpenSession(store, surface));
  session->strict = options.strict;
  session->before_commit = options.before_commit;
  PolygonAddReport total;
  TB_ASSIGN_OR_RETURN(
      std::vector<EditorFeature> features,
      ReadFeatures(options, *session->crs, options.each ? &total.failures : nullptr));
  if (features.empty() && !total.failures.empty())
    return Status::InvalidArgument("no valid feature to add; the first: " + total.failures[0]);
  if (features.empty()) return Status::InvalidArgument(options.file + ": no features to add");
  const auto progress = [&](double done) {
    if (options.progress) options.progress(done / static_cast<double>(features.size()));
  };
  if (!options.each) {
    std::vector<NewFeature> prepared;
    for (EditorFeature& f : features) {
      TB_ASSIGN_OR_RETURN(NewFeature n, Prepare(*session, std::move(f)));
      TB_RETURN_IF_ERROR(RefuseOutside(*session, n));
      prepared.push_back(std::move(n));
      progress(0.5 * static_cast<double>(prepared.size()));
    }
    return ApplyEdit(*session, std::move(prepared), {}, "polygon add");
  }
  TB_ASSIGN_OR_RETURN(session->load_points, LoadPointsThatReadTheSurface(store, surface, features));
  double done = 0;
  for (EditorFeature& f : features) {
    progress(done++);
    const std::string label = f.label;
    bool outside = false;
    auto one = [&]() -> Result<PolygonAddReport> {
      TB_ASSIGN_OR_RETURN(NewFeature n, Prepare(*session, std::move(f)));
      outside = n.verdict == ClipVerdict::kOutside;
      if (outside) return Status::InvalidArgument(WhollyOutsideMessage(session->surface.name));
      std::vector<NewFeature> single;
      single.push_back(std::move(n));
      return ApplyEdit(*session, std::move(single), {}, "polygon add");
    }();
    if (!one.ok()) {
      (outside ? total.skipped : total.failures).push_back(label + ": " + one.status().message());
      continue;
    }
    total.clipped.insert(total.clipped.end(), one->clipped.begin(), one->clipped.end());
    if (total.first_feature_id == 0) total.first_feature_id = one->first_feature_id;
    total.feature_ids.insert(total.feature_ids.end(), one->feature_ids.begin(),
                             one->feature_ids.end());
    total.features += one->features;
    total.ring_vertices += one->ring_vertices;
    total.removed += one->removed;
    total.added += one->added;
    total.refinement_points += one->refinement_points;
    total.visible += one->visible;
    total.mesh_kept += one->mesh_kept;
    total.surface_reads += one->surface_reads;
    total.tx = one->tx;
  }
  return total;
}

Result<PolygonAddReport> RemovePolygon(Store& store, int64_t id,
                                       const BeforeCommit& before_commit) {
  TB_ASSIGN_OR_RETURN(SurfaceInfo surface, SurfaceOfFeature(store, id));
  TB_ASSIGN_OR_RETURN(auto session, OpenSession(store, surface));
  session->before_commit = before_commit;
  return ApplyEdit(*session, {}, {id}, "polygon remove");
}

Result<PolygonAddReport> UpdatePolygon(Store& store, int64_t id, const PolygonAddOptions& options) {
  TB_ASSIGN_OR_RETURN(SurfaceInfo surface, SurfaceOfFeature(store, id));
  TB_ASSIGN_OR_RETURN(EditorFeature old, LoadFeature(store, surface, id));
  PolygonAddOptions o = options;
  if (!o.mode) o.mode = old.mode;
  if (!o.level) o.level = old.level;
  if (!o.z_from_given && IsLineMode(*o.mode)) o.z_from = old.z_from;
  TB_RETURN_IF_ERROR(CheckModeOptions(o));
  TB_ASSIGN_OR_RETURN(auto session, OpenSession(store, surface));
  session->strict = o.strict;
  session->before_commit = o.before_commit;
  TB_ASSIGN_OR_RETURN(std::vector<EditorFeature> read, ReadFeatures(o, *session->crs));
  if (read.empty()) return Status::InvalidArgument(o.file + ": no features to update with");
  EditorFeature merged = read.front();
  for (size_t k = 1; k < read.size(); ++k) {
    merged.polygons.insert(merged.polygons.end(), read[k].polygons.begin(), read[k].polygons.end());
    merged.lines.insert(merged.lines.end(), read[k].lines.begin(), read[k].lines.end());
    merged.line_z.insert(merged.line_z.end(), read[k].line_z.begin(), read[k].line_z.end());
  }
  if (o.tag.empty() && o.tag_field.empty() && !merged.tag) merged.tag = old.tag;
  if (merged.attributes.empty()) merged.attributes = old.attributes;
  TB_ASSIGN_OR_RETURN(NewFeature n, Prepare(*session, std::move(merged)));
  TB_RETURN_IF_ERROR(RefuseOutside(*session, n));
  std::vector<NewFeature> added;
  added.push_back(std::move(n));
  return ApplyEdit(*session, std::move(added), {id}, "polygon update");
}

Result<PolygonAddReport> ApplyFeatureEdit(Store& store, const SurfaceInfo& surface,
                                          std::vector<EditorFeature> restore,
                                          const std::vector<int64_t>& remove,
                                          const std::string& action) {
  TB_ASSIGN_OR_RETURN(auto session, OpenSession(store, surface));
  session->in_caller_transaction = true;
  std::vector<NewFeature> added;
  for (EditorFeature& f : restore) {
    TB_ASSIGN_OR_RETURN(NewFeature n, Prepare(*session, std::move(f)));
    added.push_back(std::move(n));
  }
  return ApplyEdit(*session, std::move(added), remove, action);
}

}  // namespace tinbase
