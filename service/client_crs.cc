// Coordinates between the store's CRS and a client's.
#include "service/client_crs.h"

#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>

#include "core/geometry/reproject.h"

namespace tinbase::service {

struct StoreCrs::Transform {
  std::unique_ptr<OGRCoordinateTransformation> ogr;
};

StoreCrs::StoreCrs(std::string wkt, Crs crs, Crs lonlat)
    : wkt_(std::move(wkt)),
      crs_(std::move(crs)),
      lonlat_(std::move(lonlat)),
      to_lonlat_(std::make_unique<Transform>()) {
  to_lonlat_->ogr.reset(OGRCreateCoordinateTransformation(&crs_.ogr(), &lonlat_.ogr()));
}

StoreCrs::~StoreCrs() = default;

Result<const StoreCrs*> StoreCrs::Of(Store& store) {
  thread_local std::unique_ptr<StoreCrs> cached;
  TB_ASSIGN_OR_RETURN(std::optional<std::string> wkt, store.GetMeta("crs_wkt"));
  if (!wkt) return static_cast<const StoreCrs*>(nullptr);
  if (cached == nullptr || cached->wkt_ != *wkt) {
    cached.reset();
    TB_ASSIGN_OR_RETURN(Crs crs, Crs::FromWkt(*wkt));
    TB_ASSIGN_OR_RETURN(Crs lonlat, LonLatCrs());
    auto made = std::make_unique<StoreCrs>(*wkt, std::move(crs), std::move(lonlat));
    if (made->to_lonlat_->ogr == nullptr)
      return Status::InvalidArgument("no coordinate transformation from " + made->crs_.Label() +
                                     " to lon/lat");
    cached = std::move(made);
  }
  return static_cast<const StoreCrs*>(cached.get());
}

Status StoreCrs::ToLonLat(std::vector<TinVertex>& vertices) const {
  std::vector<double> x(vertices.size()), y(vertices.size());
  for (size_t i = 0; i < vertices.size(); ++i) x[i] = vertices[i].x, y[i] = vertices[i].y;
  std::vector<int> ok(vertices.size(), 0);
  to_lonlat_->ogr->Transform(vertices.size(), x.data(), y.data(), nullptr, ok.data());
  for (size_t i = 0; i < vertices.size(); ++i) {
    if (!ok[i] || !std::isfinite(x[i]) || !std::isfinite(y[i]))
      return Status::InvalidArgument("vertex " + std::to_string(i) + " (" +
                                     std::to_string(vertices[i].x) + ", " +
                                     std::to_string(vertices[i].y) + ") does not transform from " +
                                     crs_.Label() + " to lon/lat");
  }
  for (size_t i = 0; i < vertices.size(); ++i) vertices[i].x = x[i], vertices[i].y = y[i];
  return Status::Ok();
}

Result<Crs> LonLatCrs() { return Crs::FromUserInput("EPSG:4326"); }

Result<std::vector<Point2>> PointsToStore(const StoreCrs* store_crs,
                                          const std::optional<Crs>& client,
                                          std::vector<Point2> points) {
  if (!client) return points;
  if (store_crs == nullptr)
    return Status::InvalidArgument("the store has no CRS, so coordinates in " + client->Label() +
                                   " cannot be moved into it: give them in the store's units");
  std::vector<TinVertex> v(points.size());
  for (size_t i = 0; i < points.size(); ++i) v[i].x = points[i].x, v[i].y = points[i].y;
  TB_RETURN_IF_ERROR(ReprojectXy(*client, store_crs->crs(), v));
  for (size_t i = 0; i < points.size(); ++i) points[i] = {v[i].x, v[i].y};
  return points;
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
  TB_ASSIGN_OR_RETURN(Crs lonlat, LonLatCrs());
  std::vector<TinVertex> moved = std::move(ring);
  TB_RETURN_IF_ERROR(ReprojectXy(*store_crs, lonlat, moved));
  std::array<double, 4> box = {moved.front().x, moved.front().y, moved.front().x, moved.front().y};
  for (const TinVertex& v : moved) {
    box[0] = std::min(box[0], v.x), box[1] = std::min(box[1], v.y);
    box[2] = std::max(box[2], v.x), box[3] = std::max(box[3], v.y);
  }
  return std::optional<std::array<double, 4>>(box);
}

}  // namespace tinbase::service
