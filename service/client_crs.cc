// Coordinates between the store's CRS and a client's.
#include "service/client_crs.h"

#include <algorithm>

#include "core/geometry/reproject.h"

namespace tinbase::service {

Result<Crs> LonLatCrs() { return Crs::FromUserInput("EPSG:4326"); }

Result<std::vector<Point2>> PointsToStore(const std::optional<Crs>& store_crs,
                                          const std::optional<Crs>& client,
                                          std::vector<Point2> points) {
  if (!client) return points;
  if (!store_crs)
    return Status::InvalidArgument("the store has no CRS, so coordinates in " + client->Label() +
                                   " cannot be moved into it: give them in the store's units");
  std::vector<TinVertex> v(points.size());
  for (size_t i = 0; i < points.size(); ++i) v[i].x = points[i].x, v[i].y = points[i].y;
  TB_RETURN_IF_ERROR(ReprojectXy(*client, *store_crs, v));
  for (size_t i = 0; i < points.size(); ++i) points[i] = {v[i].x, v[i].y};
  return points;
}

Result<std::vector<TinVertex>> VerticesToLonLat(const Crs& store_crs,
                                                std::vector<TinVertex> vertices) {
  TB_ASSIGN_OR_RETURN(Crs lonlat, LonLatCrs());
  TB_RETURN_IF_ERROR(ReprojectXy(store_crs, lonlat, vertices));
  return vertices;
}

Result<std::optional<std::array<double, 4>>> BoxToLonLat(const std::optional<Crs>& store_crs,
                                                         double min_x, double min_y, double max_x,
                                                         double max_y) {
  if (!store_crs) return std::optional<std::array<double, 4>>();
  std::vector<TinVertex> ring;
  const double xs[] = {min_x, (min_x + max_x) / 2, max_x};
  const double ys[] = {min_y, (min_y + max_y) / 2, max_y};
  for (double x : xs)
    for (double y : ys) ring.push_back(TinVertex{x, y, 0, VertexKind::kDem});
  TB_ASSIGN_OR_RETURN(std::vector<TinVertex> moved, VerticesToLonLat(*store_crs, std::move(ring)));
  std::array<double, 4> box = {moved.front().x, moved.front().y, moved.front().x, moved.front().y};
  for (const TinVertex& v : moved) {
    box[0] = std::min(box[0], v.x), box[1] = std::min(box[1], v.y);
    box[2] = std::max(box[2], v.x), box[3] = std::max(box[3], v.y);
  }
  return std::optional<std::array<double, 4>>(box);
}

}  // namespace tinbase::service
