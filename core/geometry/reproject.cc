#include "core/geometry/reproject.h"

#include <ogr_spatialref.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

namespace tinbase {

Status ReprojectXy(const Crs& from, const Crs& to, std::vector<TinVertex>& vertices) {
  std::unique_ptr<OGRCoordinateTransformation> transform(
      OGRCreateCoordinateTransformation(&from.ogr(), &to.ogr()));
  if (!transform) {
    return Status::InvalidArgument("no coordinate transformation from " + from.Label() + " to " +
                                   to.Label());
  }
  std::vector<double> x(vertices.size()), y(vertices.size());
  for (size_t i = 0; i < vertices.size(); ++i) {
    x[i] = vertices[i].x;
    y[i] = vertices[i].y;
  }
  std::vector<int> ok(vertices.size(), 0);
  transform->Transform(vertices.size(), x.data(), y.data(), nullptr, ok.data());
  for (size_t i = 0; i < vertices.size(); ++i) {
    if (!ok[i] || !std::isfinite(x[i]) || !std::isfinite(y[i])) {
      // %g, not std::to_string: a huge coordinate would print as hundreds of digits.
      char point[64];
      std::snprintf(point, sizeof point, "(%.10g, %.10g)", vertices[i].x, vertices[i].y);
      return Status::InvalidArgument("point " + std::to_string(i) + " " + point +
                                     " does not transform from " + from.Label() + " to " +
                                     to.Label());
    }
  }
  for (size_t i = 0; i < vertices.size(); ++i) {
    vertices[i].x = x[i];
    vertices[i].y = y[i];
  }
  return Status::Ok();
}

void ConvertHeightUnits(const Crs& from, const Crs& to, std::vector<TinVertex>& vertices) {
  const double factor = from.VerticalMetresPerUnit() / to.VerticalMetresPerUnit();
  if (factor == 1.0) return;
  for (TinVertex& v : vertices) v.z *= factor;
}

}  // namespace tinbase
