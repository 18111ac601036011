#include "core/export/local_frame.h"

#include <cpl_conv.h>
#include <ogr_spatialref.h>

#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <memory>

#include "core/geometry/reproject.h"

namespace tinbase {

namespace {

// The geographic system of `crs`'s own datum (longitude, latitude in degrees).
Result<Crs> GeographicOf(const Crs& crs) {
  std::unique_ptr<OGRSpatialReference> geog(crs.ogr().CloneGeogCS());
  if (!geog) return Status::InvalidArgument(crs.Label() + " has no geographic system");
  char* wkt = nullptr;
  const char* options[] = {"FORMAT=WKT2_2018", nullptr};
  geog->exportToWkt(&wkt, options);
  std::string text = wkt != nullptr ? wkt : "";
  CPLFree(wkt);
  return Crs::FromWkt(text);
}

}  // namespace

Result<LocalFrame> ToLocalFrame(const Tin& tin, const Crs* crs, const MeshSelection& s) {
  assert(!s.vertices.empty());
  LocalFrame frame;
  std::vector<TinVertex> points;
  points.reserve(s.vertices.size() + 1);
  double lo[3], hi[3];
  std::fill(lo, lo + 3, std::numeric_limits<double>::infinity());
  std::fill(hi, hi + 3, -std::numeric_limits<double>::infinity());
  for (uint32_t v : s.vertices) {
    const TinVertex& p = tin.vertices[v];
    points.push_back(p);
    const double c[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c[k]), hi[k] = std::max(hi[k], c[k]);
  }
  frame.x0 = lo[0] / 2 + hi[0] / 2;
  frame.y0 = lo[1] / 2 + hi[1] / 2;
  frame.z0 = lo[2] / 2 + hi[2] / 2;
  frame.enu.resize(s.vertices.size());
  if (crs == nullptr) {
    for (size_t i = 0; i < points.size(); ++i)
      frame.enu[i] = {points[i].x - frame.x0, points[i].y - frame.y0, points[i].z - frame.z0};
    return frame;
  }

  TB_ASSIGN_OR_RETURN(Crs geographic, GeographicOf(*crs));
  // The origin rides along as the last point, so it goes through the very same transformation.
  points.push_back({frame.x0, frame.y0, frame.z0, VertexKind::kUser});
  if (!crs->IsGeographic()) TB_RETURN_IF_ERROR(ReprojectXy(*crs, geographic, points));
  ConvertHeightUnits(*crs, geographic, points);
  const TinVertex origin = points.back();
  points.pop_back();
  // A geographic store holding projected numbers (or a broken transformation) would otherwise
  // become NaN positions in the file.
  for (size_t i = 0; i < points.size(); ++i) {
    const TinVertex& p = points[i];
    if (!(std::abs(p.y) <= 90) || !std::isfinite(p.x) || !std::isfinite(p.z)) {
      const TinVertex& v = tin.vertices[s.vertices[i]];
      return Status::InvalidArgument("vertex (" + std::to_string(v.x) + ", " + std::to_string(v.y) +
                                     ") is not a place on " + "the earth in " + crs->Label() +
                                     " (latitude " + std::to_string(p.y) + ")");
    }
  }

  OGRErr err = OGRERR_NONE;
  frame.semi_major = geographic.ogr().GetSemiMajor(&err);
  frame.inverse_flattening = geographic.ogr().GetInvFlattening(&err);
  const GeographicLib::Geocentric earth(
      frame.semi_major, frame.inverse_flattening > 0 ? 1 / frame.inverse_flattening : 0);
  const GeographicLib::LocalCartesian enu(origin.y, origin.x, origin.z, earth);
  for (size_t i = 0; i < points.size(); ++i) {
    double e = 0, n = 0, u = 0;
    enu.Forward(points[i].y, points[i].x, points[i].z, e, n, u);
    frame.enu[i] = {e, n, u};
  }
  frame.geodetic = true;
  frame.latitude = origin.y;
  frame.longitude = origin.x;
  frame.height = origin.z;
  frame.geographic_crs = geographic.Label();
  return frame;
}

}  // namespace tinbase
