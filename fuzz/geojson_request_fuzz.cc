// Fuzzes ParseGeoJsonFeatures (service/geojson_request.h), the body of POST and PUT
// /surfaces/{s}/features: any bytes end in features or in one error line; every feature read has
// geometry, every coordinate is finite, and every polygon passed validation (a shell of at least
// three vertices); a 3D line's z, when kept, is one finite number per vertex. The first byte
// picks whether the body's coordinates are reprojected (from EPSG:4326) or already in the store's
// CRS (EPSG:32632), and whether it is read as features or as the survey points of POST
// /surfaces/{s}/points (ParseGeoJsonPoints: every point finite, one label each).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string_view>

#include "core/geometry/crs.h"
#include "service/geojson_request.h"

namespace {

bool Finite(const tinbase::Point2& p) { return std::isfinite(p.x) && std::isfinite(p.y); }

void CheckFeature(const tinbase::MemoryFeature& f) {
  if (f.polygons.empty() && f.lines.empty()) std::abort();
  for (const tinbase::Polygon& polygon : f.polygons) {
    if (polygon.shell.size() < 3) std::abort();
    for (const tinbase::Point2& p : polygon.shell)
      if (!Finite(p)) std::abort();
    for (const auto& hole : polygon.holes)
      for (const tinbase::Point2& p : hole)
        if (!Finite(p)) std::abort();
  }
  for (const auto& line : f.lines) {
    if (line.size() < 2) std::abort();
    for (const tinbase::Point2& p : line)
      if (!Finite(p)) std::abort();
  }
  if (f.line_z.size() != f.lines.size()) std::abort();
  for (size_t k = 0; k < f.line_z.size(); ++k) {
    if (!f.line_z[k].empty() && f.line_z[k].size() != f.lines[k].size()) std::abort();
    for (double z : f.line_z[k])
      if (!std::isfinite(z)) std::abort();
  }
  if (f.level && !std::isfinite(*f.level)) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const tinbase::Crs store_crs = *tinbase::Crs::FromUserInput("EPSG:32632");
  static const tinbase::Crs lonlat = *tinbase::Crs::FromUserInput("EPSG:4326");
  if (size == 0) return 0;
  std::optional<tinbase::Crs> source;
  if (data[0] & 1) source = lonlat;
  const std::string_view body(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] & 2) {
    auto points = tinbase::service::ParseGeoJsonPoints(body, source, store_crs);
    if (!points.ok()) {
      if (points.status().message().find('\n') != std::string::npos) std::abort();
      return 0;
    }
    if (points->points.empty() || points->labels.size() != points->points.size()) std::abort();
    for (const tinbase::TinVertex& p : points->points)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
    return 0;
  }
  auto features = tinbase::service::ParseGeoJsonFeatures(body, source, store_crs);
  if (!features.ok()) {
    if (features.status().message().find('\n') != std::string::npos) std::abort();
    return 0;
  }
  if (features->empty()) std::abort();
  for (const tinbase::MemoryFeature& f : *features) CheckFeature(f);
  return 0;
}
