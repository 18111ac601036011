#include "db/query/measure_source.h"

#include "core/vector/polygon_source.h"
#include "db/feature_store.h"

namespace tinbase {

Result<std::pair<std::optional<Crs>, MetricFrame>> StoreFrame(Store& store) {
  TB_ASSIGN_OR_RETURN(std::optional<Crs> crs, store.GetCrs());
  TB_ASSIGN_OR_RETURN(MetricFrame frame, MetricFrameFor(crs ? &*crs : nullptr));
  return std::make_pair(std::move(crs), frame);
}

Result<MeasureSource> LoadMeasureSource(Store& store, const std::string& name,
                                        SurfaceFilter filter) {
  MeasureSource out;
  SurfaceStore surfaces(store);
  TB_ASSIGN_OR_RETURN(out.surface, surfaces.Find(name));
  filter.visible_only = true;
  TB_ASSIGN_OR_RETURN(out.part, SelectSurface(store, out.surface, filter));
  TB_ASSIGN_OR_RETURN(auto frame, StoreFrame(store));
  out.crs = std::move(frame.first);
  out.frame = frame.second;
  return out;
}

Result<std::vector<Polygon>> LoadMeasurePolygons(Store& store,
                                                 const std::vector<SurfaceInfo>& surfaces,
                                                 int64_t feature, const std::string& path) {
  if (feature != 0) {
    std::string names;
    for (const SurfaceInfo& surface : surfaces) {
      Result<EditorFeature> f = LoadFeature(store, surface, feature);
      if (f.ok()) {
        if (f->polygons.empty())
          return Status::InvalidArgument("feature " + std::to_string(feature) +
                                         " is a breakline: it has no inside to measure");
        return f->polygons;
      }
      if (f.status().code() != StatusCode::kNotFound) return f.status();
      names += (names.empty() ? "'" : " or '") + surface.name + "'";
    }
    return Status::NotFound("no feature " + std::to_string(feature) + " on surface " + names);
  }
  TB_ASSIGN_OR_RETURN(std::optional<Crs> crs, store.GetCrs());
  VectorSourceOptions options;
  options.target_crs = crs;
  TB_ASSIGN_OR_RETURN(std::vector<PolygonFeature> features, ReadPolygonFeatures(path, options));
  std::vector<Polygon> polygons;
  for (PolygonFeature& f : features) {
    for (Polygon& p : f.polygons) polygons.push_back(std::move(p));
  }
  return polygons;
}

}  // namespace tinbase
