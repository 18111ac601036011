#include "core/export/local_frame.h"

#include <cpl_conv.h>
#include <ogr_spatialref.h>
#include <tbb/parallel_for.h>

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

// `points` from `crs` to its geographic system `geographic`, heights in metres. A geographic
// store holding projected numbers (or a broken transformation) would otherwise become NaN
// positions in the file, so a point off the earth is an error naming it.
Status ToGeographic(const Crs& crs, const Crs& geographic, std::vector<TinVertex>& points) {
  std::vector<TinVertex> original;
  if (!crs.IsGeographic()) {
    original = points;
    TB_RETURN_IF_ERROR(ReprojectXy(crs, geographic, points));
  }
  ConvertHeightUnits(crs, geographic, points);
  for (size_t i = 0; i < points.size(); ++i) {
    const TinVertex& p = points[i];
    if (std::abs(p.y) <= 90 && std::isfinite(p.x) && std::isfinite(p.z)) continue;
    const TinVertex& v = original.empty() ? p : original[i];
    return Status::InvalidArgument("vertex (" + std::to_string(v.x) + ", " + std::to_string(v.y) +
                                   ") is not a place on the earth in " + crs.Label() +
                                   " (latitude " + std::to_string(p.y) + ")");
  }
  return Status::Ok();
}

constexpr size_t kChunk = size_t{1} << 16;  // vertices per parallel task

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
  std::vector<TinVertex> origin_point = {{frame.x0, frame.y0, frame.z0, VertexKind::kUser}};
  TB_RETURN_IF_ERROR(ToGeographic(*crs, geographic, origin_point));
  const TinVertex origin = origin_point[0];
  OGRErr err = OGRERR_NONE;
  frame.semi_major = geographic.ogr().GetSemiMajor(&err);
  frame.inverse_flattening = geographic.ogr().GetInvFlattening(&err);
  const GeographicLib::Geocentric earth(
      frame.semi_major, frame.inverse_flattening > 0 ? 1 / frame.inverse_flattening : 0);
  const GeographicLib::LocalCartesian enu(origin.y, origin.x, origin.z, earth);

  // Chunks on TBB's threads, each with its own copies of the two systems (an
  // OGRSpatialReference is not safe to share between threads); every point is transformed on
  // its own, so the result does not depend on the thread count. The first failing chunk's error
  // is reported, whichever thread met it first.
  const size_t chunks = (points.size() + kChunk - 1) / kChunk;
  std::vector<Crs> from(chunks, *crs), to(chunks, geographic);
  std::vector<Status> errors(chunks);
  tbb::parallel_for(size_t{0}, chunks, [&](size_t c) {
    const size_t begin = c * kChunk, end = std::min(points.size(), begin + kChunk);
    std::vector<TinVertex> part(points.begin() + static_cast<ptrdiff_t>(begin),
                                points.begin() + static_cast<ptrdiff_t>(end));
    errors[c] = ToGeographic(from[c], to[c], part);
    if (!errors[c].ok()) return;
    for (size_t i = 0; i < part.size(); ++i) {
      double e = 0, n = 0, u = 0;
      enu.Forward(part[i].y, part[i].x, part[i].z, e, n, u);
      frame.enu[begin + i] = {e, n, u};
    }
  });
  for (const Status& e : errors) TB_RETURN_IF_ERROR(e);
  frame.geodetic = true;
  frame.latitude = origin.y;
  frame.longitude = origin.x;
  frame.height = origin.z;
  frame.geographic_crs = geographic.Label();
  return frame;
}

}  // namespace tinbase
