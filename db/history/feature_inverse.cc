#include "db/history/feature_inverse.h"

#include <utility>

#include "db/edit/mass_points.h"
#include "db/polygon_editor.h"

namespace tinbase {

namespace {

// Polygons and lines: the polygon editor drapes the restored versions again on the DEM, as the
// edit that first added them did (their stored geometry is the undraped input), so they come back
// with the same ring vertices.
Result<InverseResult> ApplyEditorInverse(Store& store, const SurfaceInfo& surface,
                                         const FeatureInverse& inverse, const std::string& action) {
  std::vector<EditorFeature> restore;
  for (const FeatureVersion& v : inverse.restore) {
    TB_ASSIGN_OR_RETURN(EditorFeature f, EditorFeatureOf(v));
    restore.push_back(std::move(f));
  }
  TB_ASSIGN_OR_RETURN(PolygonAddReport report,
                      ApplyFeatureEdit(store, surface, std::move(restore), inverse.remove, action));
  return InverseResult{report.tx, report.removed, report.added};
}

// Mass points: their points go out and come back with their own z, through the points editor.
Result<InverseResult> ApplyPointsInverse(Store& store, const SurfaceInfo& surface,
                                         const FeatureInverse& inverse, const std::string& action) {
  std::vector<EditorFeature> restore;
  for (const FeatureVersion& v : inverse.restore) {
    TB_ASSIGN_OR_RETURN(EditorFeature f, EditorFeatureOf(v));
    restore.push_back(std::move(f));
  }
  TB_ASSIGN_OR_RETURN(PointsReport report,
                      ApplyPointsEdit(store, surface, std::move(restore), inverse.remove, action));
  return InverseResult{report.tx, report.removed, report.added};
}

}  // namespace

std::string_view InverseFamily(std::string_view mode) {
  return mode == "points" ? "points" : "editor";
}

Result<InverseApplier> InverseFor(std::string_view family) {
  if (family == "editor") return &ApplyEditorInverse;
  if (family == "points") return &ApplyPointsInverse;
  return Status::InvalidArgument("reverting edits of " + std::string(family) +
                                 " features is not supported by this build");
}

}  // namespace tinbase
