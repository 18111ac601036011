// The features a mesh export describes, read from a store.
#include "db/export/export_features.h"

#include "db/feature_store.h"

namespace tinbase {

Status AddExportFeatures(Store& store, const SurfaceInfo& surface, const Tin& tin,
                         ExportOptions& options) {
  TB_ASSIGN_OR_RETURN(std::vector<EditorFeature> features, LoadFeatures(store, surface));
  for (const EditorFeature& f : features) {
    ExportFeature e;
    e.id = f.id;
    e.mode = f.mode;
    e.tag = f.tag;
    e.attributes = f.attributes;
    if (!f.polygons.empty()) e.inside = InsideOf(f);
    options.features.push_back(std::move(e));
  }
  options.triangle_feature = OwningFeatures(tin, options.features);
  return Status::Ok();
}

}  // namespace tinbase
