#include "db/edit/mass_points.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>
#include <tuple>
#include <utility>

#include "core/geometry/polygon.h"
#include "core/vector/survey_points.h"
#include "db/change_log.h"
#include "db/dem_store.h"
#include "db/edit/point_screen.h"
#include "db/edit/surface_of_feature.h"
#include "db/edit/update_engine.h"
#include "db/history/feature_versions.h"
#include "db/history/mesh_image_store.h"
#include "db/mesh_cache.h"
#include "db/surface_store.h"

namespace tinbase {
namespace {

// The range a survey z may take: the DEM's relief widened by ten times its height and by at
// least kZMargin, as for replace levels (db/polygon_editor.cc): beyond it a z is a unit or typing
// mistake, and the spike it makes would be steeper than any check can follow.
constexpr double kZMargin = 10000;

std::string FormatNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", v);
  return text;
}

// What every points edit of one surface needs: the surface and its DEM.
struct PointsSession {
  explicit PointsSession(Store& s) : store(s), dems(s) {}
  Store& store;
  SurfaceInfo surface;
  DemStore dems;
  DemInfo dem;
};

Result<std::unique_ptr<PointsSession>> OpenSession(Store& store, const SurfaceInfo& surface) {
  auto session = std::make_unique<PointsSession>(store);
  session->surface = surface;
  if (!surface.dem)
    return Status::InvalidArgument("surface '" + surface.name + "' is not draped on a DEM");
  TB_ASSIGN_OR_RETURN(session->dem, session->dems.FindById(*surface.dem));
  return session;
}

// InvalidArgument naming the first point with a coordinate that is not finite or a z outside
// the accepted range.
Status CheckCoordinates(PointsSession& session, const std::vector<TinVertex>& points,
                        const std::vector<std::string>& labels) {
  TB_ASSIGN_OR_RETURN(auto relief, session.dems.Relief(session.dem));
  const double margin = std::max(10 * (relief.second - relief.first), kZMargin);
  const double low = relief.first - margin, high = relief.second + margin;
  for (size_t i = 0; i < points.size(); ++i) {
    const TinVertex& p = points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return Status::InvalidArgument(labels[i] + ": a coordinate is not a finite number");
    const double z = p.z;
    if (z >= low && z <= high) continue;
    return Status::InvalidArgument(labels[i] + ": z " + FormatNumber(z) +
                                   " is far outside the relief of surface '" +
                                   session.surface.name + "' (from " + FormatNumber(low) + " to " +
                                   FormatNumber(high) + " is accepted)");
  }
  return Status::Ok();
}

// One edit's transaction: begun, its change row appended, the mesh cache started.
struct PointsTransaction {
  std::unique_ptr<WriteTransaction> tx;
  int64_t number = 0;
};

Result<PointsTransaction> Begin(PointsSession& session, MeshCache& mesh, const char* action) {
  PointsTransaction out;
  TB_ASSIGN_OR_RETURN(out.tx, session.store.BeginWrite());
  Change change;
  change.surface = session.surface.id;
  change.action = action;
  TB_ASSIGN_OR_RETURN(out.number, AppendChange(session.store, change));
  TB_RETURN_IF_ERROR(mesh.Begin(out.number).status());
  return out;
}

// Completes the `changes` row of `tx`: the first feature added (else removed), the triangle
// counts and the extent of `box` and the region.
Status RecordChange(Store& store, int64_t tx, int64_t feature, const EditResult& result, Box box) {
  box.Add(result.region);
  TB_ASSIGN_OR_RETURN(Statement * update,
                      store.db().Cached("UPDATE changes SET feature = ?, removed = ?, added = ?, "
                                        "min_x = ?, min_y = ?, max_x = ?, max_y = ? WHERE tx = ?"));
  update->Bind(1, feature).Bind(2, result.removed).Bind(3, result.added);
  update->Bind(4, box.min_x).Bind(5, box.min_y).Bind(6, box.max_x).Bind(7, box.max_y);
  return update->Bind(8, tx).Run();
}

// Runs `engine` on `edit` with the surface's features after the edit, in id order. The engine
// is the caller's so that it lives until the commit (its raised page cache holds the rows the
// edit writes, update_engine.h).
Result<EditResult> ApplyEdit(PointsSession& session, UpdateEngine& engine, LocalEdit& edit) {
  TB_ASSIGN_OR_RETURN(edit.features, LoadFeatures(session.store, session.surface));
  const std::set<int64_t> removing(edit.remove.begin(), edit.remove.end());
  std::erase_if(edit.features, [&](const EditorFeature& f) { return removing.count(f.id) > 0; });
  return engine.Apply(edit);
}

}  // namespace

Result<PointsReport> AddPoints(Store& store, const PointsAddOptions& options) {
  TB_ASSIGN_OR_RETURN(SurfaceInfo surface, SurfaceStore(store).Find(options.surface));
  TB_ASSIGN_OR_RETURN(auto session, OpenSession(store, surface));
  SurveyPoints input;
  if (options.points) {
    if (options.labels.size() != options.points->size())
      return Status::InvalidArgument("one label per point is needed");
    input.points = *options.points;
    input.labels = options.labels;
    for (TinVertex& p : input.points) p.kind = VertexKind::kUser;
  } else {
    TB_ASSIGN_OR_RETURN(std::optional<Crs> crs, store.GetCrs());
    TB_ASSIGN_OR_RETURN(input, ReadSurveyPoints(options.file, crs));
  }
  if (input.points.empty()) return Status::InvalidArgument(options.file + ": no points");
  TB_RETURN_IF_ERROR(CheckCoordinates(*session, input.points, input.labels));

  PointsReport report;
  report.points_in = static_cast<int64_t>(input.points.size());
  report.reprojected_from = input.reprojected_from;
  MeshCache mesh(store, surface);
  TB_ASSIGN_OR_RETURN(PointsTransaction tx, Begin(*session, mesh, "points add"));
  report.tx = tx.number;
  const EditContext ctx{store, surface, session->dems, session->dem, mesh};
  TB_ASSIGN_OR_RETURN(ScreenedPoints screened, ScreenPoints(ctx, input.points, input.labels));
  for (const SnappedPoint& s : screened.snapped)
    report.snapped.push_back(DescribeSnap(s, input.points, input.labels));
  if (screened.kept.empty())
    return Status::InvalidArgument("every point snapped onto a vertex already there; the first: " +
                                   report.snapped.front());

  EditorFeature feature;
  feature.mode = FeatureMode::kPoints;
  feature.label = options.file.empty() ? std::string("points")
                                       : std::filesystem::path(options.file).filename().string();
  feature.tag = options.tag;
  std::vector<size_t> file_order = screened.kept;
  std::sort(file_order.begin(), file_order.end());
  for (size_t i : file_order) feature.points.push_back(input.points[i]);
  TB_RETURN_IF_ERROR(WriteFeature(store, surface, tx.number, feature));
  TB_RETURN_IF_ERROR(SettleFeatureId(store, 0, feature));
  TB_RETURN_IF_ERROR(RecordFeatureVersions(store, tx.number, {feature.id}, {}));

  LocalEdit edit;
  for (size_t i : screened.kept) edit.add.push_back({{input.points[i]}, false, feature.id});
  UpdateEngine engine(store, session->surface, session->dems, session->dem);
  engine.set_mesh_cache(&mesh);
  MeshImage image;
  engine.set_mesh_image(&image);
  TB_ASSIGN_OR_RETURN(EditResult result, ApplyEdit(*session, engine, edit));
  TB_RETURN_IF_ERROR(RecordChange(store, tx.number, feature.id, result, screened.box));
  TB_RETURN_IF_ERROR(RecordMeshImage(store, tx.number, std::move(image)));
  if (options.before_commit) TB_RETURN_IF_ERROR(options.before_commit(store, tx.number));
  TB_RETURN_IF_ERROR(tx.tx->Commit());
  report.inserted = static_cast<int64_t>(screened.kept.size());
  report.features_added.push_back(feature.id);
  report.removed = result.removed;
  report.added = result.added;
  report.refinement_points = result.refinement_points;
  return report;
}

Result<PointsReport> RemovePoints(Store& store, const PointsRemoveOptions& options) {
  if (options.feature.has_value() == options.box.has_value())
    return Status::InvalidArgument("give a feature or a box of points to remove, not both");
  SurfaceInfo surface;
  if (options.feature) {
    TB_ASSIGN_OR_RETURN(surface, SurfaceOfFeature(store, *options.feature));
  } else {
    TB_ASSIGN_OR_RETURN(surface, SurfaceStore(store).Find(options.surface));
  }
  TB_ASSIGN_OR_RETURN(auto session, OpenSession(store, surface));
  MeshCache mesh(store, surface);
  TB_ASSIGN_OR_RETURN(PointsTransaction tx, Begin(*session, mesh, "points remove"));
  TB_ASSIGN_OR_RETURN(std::vector<EditorFeature> features, LoadFeatures(store, surface));
  const auto taken = [&](const TinVertex& p) {
    return !options.box || options.box->Contains(Point2{p.x, p.y});
  };
  PointsReport report;
  report.tx = tx.number;
  LocalEdit edit;
  std::vector<TinVertex> going;
  Box box;
  const EditContext ctx{store, surface, session->dems, session->dem, mesh};
  for (EditorFeature& f : features) {
    if (options.feature && f.id != *options.feature) continue;
    if (f.mode != FeatureMode::kPoints) {
      if (options.feature)
        return Status::InvalidArgument("feature " + std::to_string(f.id) + " is a " +
                                       FeatureModeName(f.mode) +
                                       " feature, not survey points (polygon remove takes it out)");
      continue;
    }
    EditorFeature rest;
    rest.mode = FeatureMode::kPoints;
    rest.label = f.label;
    rest.tag = f.tag;
    rest.attributes = f.attributes;
    size_t out = 0;
    for (const TinVertex& p : f.points) {
      if (!taken(p)) {
        rest.points.push_back(p);
        continue;
      }
      ++out;
      going.push_back(p);
      box.Add(Point2{p.x, p.y});
    }
    if (out == 0) continue;
    edit.remove.push_back(f.id);
    report.features_removed.push_back(f.id);
    if (rest.points.empty()) continue;
    TB_RETURN_IF_ERROR(WriteFeature(store, surface, tx.number, rest));
    TB_RETURN_IF_ERROR(SettleFeatureId(store, 0, rest));
    report.features_added.push_back(rest.id);
  }
  if (going.empty())
    return Status::InvalidArgument("surface '" + surface.name +
                                   "' has no survey points in the box");
  report.points_in = static_cast<int64_t>(going.size());
  for (const TinVertex& p : going) {
    TB_ASSIGN_OR_RETURN(const int64_t v, SurveyVertexAt(ctx, p));
    if (v != 0) edit.drop_vertices.push_back(v);
  }
  std::sort(edit.drop_vertices.begin(), edit.drop_vertices.end());
  edit.drop_vertices.erase(std::unique(edit.drop_vertices.begin(), edit.drop_vertices.end()),
                           edit.drop_vertices.end());
  UpdateEngine engine(store, session->surface, session->dems, session->dem);
  engine.set_mesh_cache(&mesh);
  MeshImage image;
  engine.set_mesh_image(&image);
  TB_ASSIGN_OR_RETURN(EditResult result, ApplyEdit(*session, engine, edit));
  TB_RETURN_IF_ERROR(
      RecordFeatureVersions(store, tx.number, report.features_added, report.features_removed));
  for (int64_t id : edit.remove) TB_RETURN_IF_ERROR(DeleteFeature(store, id));
  TB_RETURN_IF_ERROR(RecordChange(store, tx.number, report.features_removed.front(), result, box));
  TB_RETURN_IF_ERROR(RecordMeshImage(store, tx.number, std::move(image)));
  if (options.before_commit) TB_RETURN_IF_ERROR(options.before_commit(store, tx.number));
  TB_RETURN_IF_ERROR(tx.tx->Commit());
  report.inserted = static_cast<int64_t>(edit.drop_vertices.size());
  report.removed = result.removed;
  report.added = result.added;
  report.refinement_points = result.refinement_points;
  return report;
}

namespace {

// The points of `a` that are not in `b` (the same x, y and z), in a's order.
std::vector<TinVertex> PointsNotIn(const std::vector<TinVertex>& a,
                                   const std::vector<TinVertex>& b) {
  const auto key = [](const TinVertex& p) { return std::tuple(p.x, p.y, p.z); };
  std::set<std::tuple<double, double, double>> other;
  for (const TinVertex& p : b) other.insert(key(p));
  std::vector<TinVertex> out;
  for (const TinVertex& p : a)
    if (other.count(key(p)) == 0) out.push_back(p);
  return out;
}

}  // namespace

Result<PointsReport> ApplyPointsEdit(Store& store, const SurfaceInfo& surface,
                                     std::vector<EditorFeature> restore,
                                     const std::vector<int64_t>& remove,
                                     const std::string& action) {
  TB_ASSIGN_OR_RETURN(auto session, OpenSession(store, surface));
  MeshCache mesh(store, surface);
  Change change;
  change.surface = surface.id;
  change.action = action;
  PointsReport report;
  TB_ASSIGN_OR_RETURN(report.tx, AppendChange(store, change));
  TB_RETURN_IF_ERROR(mesh.Begin(report.tx).status());
  const EditContext ctx{store, surface, session->dems, session->dem, mesh};
  std::vector<TinVertex> going, coming;
  for (int64_t id : remove) {
    TB_ASSIGN_OR_RETURN(EditorFeature f, LoadFeature(store, surface, id));
    going.insert(going.end(), f.points.begin(), f.points.end());
  }
  LocalEdit edit;
  edit.remove = remove;
  Box box;
  for (EditorFeature& f : restore) {
    const int64_t wanted = f.id;
    TB_RETURN_IF_ERROR(WriteFeature(store, surface, report.tx, f));
    TB_RETURN_IF_ERROR(SettleFeatureId(store, wanted, f));
    report.features_added.push_back(f.id);
    box.Add(BoxOf(f));
    const std::vector<TinVertex> back = PointsNotIn(f.points, going);
    std::vector<std::string> labels(back.size(), f.label);
    TB_ASSIGN_OR_RETURN(ScreenedPoints screened, ScreenPoints(ctx, back, labels));
    for (size_t i : screened.kept) edit.add.push_back({{back[i]}, false, f.id});
    coming.insert(coming.end(), f.points.begin(), f.points.end());
  }
  for (const TinVertex& p : PointsNotIn(going, coming)) {
    TB_ASSIGN_OR_RETURN(const int64_t v, SurveyVertexAt(ctx, p));
    if (v != 0) edit.drop_vertices.push_back(v);
    box.Add(Point2{p.x, p.y});
  }
  std::sort(edit.drop_vertices.begin(), edit.drop_vertices.end());
  edit.drop_vertices.erase(std::unique(edit.drop_vertices.begin(), edit.drop_vertices.end()),
                           edit.drop_vertices.end());
  UpdateEngine engine(store, session->surface, session->dems, session->dem);
  engine.set_mesh_cache(&mesh);
  MeshImage image;
  engine.set_mesh_image(&image);
  TB_ASSIGN_OR_RETURN(EditResult result, ApplyEdit(*session, engine, edit));
  TB_RETURN_IF_ERROR(RecordFeatureVersions(store, report.tx, report.features_added, remove));
  for (int64_t id : remove) TB_RETURN_IF_ERROR(DeleteFeature(store, id));
  const int64_t first = !report.features_added.empty() ? report.features_added.front()
                                                       : (remove.empty() ? 0 : remove.front());
  TB_RETURN_IF_ERROR(RecordChange(store, report.tx, first, result, box));
  TB_RETURN_IF_ERROR(RecordMeshImage(store, report.tx, std::move(image)));
  report.features_removed = remove;
  report.inserted = static_cast<int64_t>(edit.add.size());
  report.removed = result.removed;
  report.added = result.added;
  report.refinement_points = result.refinement_points;
  return report;
}

}  // namespace tinbase
