#include "db/query/bulk_locate.h"

namespace tinbase {

Status LocatePoints(Store& store, const SurfaceInfo& surface, const std::vector<Point2>& points,
                    const LocatedPointSink& sink) {
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  PointLocator locator(store, surface);
  for (size_t i = 0; i < points.size(); ++i) {
    Result<Location> where = locator.Locate(points[i].x, points[i].y);
    if (where.ok()) {
      TB_RETURN_IF_ERROR(sink(i, points[i], &*where));
    } else if (where.status().code() == StatusCode::kNotFound) {
      TB_RETURN_IF_ERROR(sink(i, points[i], nullptr));
    } else {
      return where.status();
    }
  }
  return Status::Ok();
}

}  // namespace tinbase
