#include "db/query/cut_fill.h"

#include <memory>
#include <optional>

#include "core/measure/plan_region.h"
#include "db/query/measure_source.h"

namespace tinbase {

Result<CutFillResult> CutFill(Store& store, const CutFillRequest& request) {
  if (request.feature != 0 && !request.polygon_file.empty())
    return Status::InvalidArgument("give a polygon feature or a polygon file, not both");
  TB_ASSIGN_OR_RETURN(std::unique_ptr<ReadSnapshot> snapshot, SnapshotUnlessInTransaction(store));
  TB_ASSIGN_OR_RETURN(MeasureSource base, LoadMeasureSource(store, request.base, {}));
  TB_ASSIGN_OR_RETURN(MeasureSource top, LoadMeasureSource(store, request.top, {}));
  CutFillResult result;
  result.base = base.surface;
  result.top = top.surface;
  std::optional<PlanRegion> region;
  if (request.feature != 0 || !request.polygon_file.empty()) {
    TB_ASSIGN_OR_RETURN(std::vector<Polygon> polygons,
                        LoadMeasurePolygons(store, {base.surface, top.surface}, request.feature,
                                            request.polygon_file));
    TB_ASSIGN_OR_RETURN(region, PlanRegion::FromPolygons(polygons));
    result.inside_polygon = true;
  }
  Result<VolumeReport> volume =
      VolumeBetween(base.part.tin, top.part.tin, base.frame, region ? &*region : nullptr);
  if (!volume.ok()) {
    return Status::InvalidArgument("surfaces '" + base.surface.name + "' and '" + top.surface.name +
                                   "' do not overlap" + (region ? " inside the polygon" : ""));
  }
  result.volume = *volume;
  return result;
}

}  // namespace tinbase
