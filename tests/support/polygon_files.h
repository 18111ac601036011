// Polygon files for tests: rings written as GeoJSON features in a given CRS, and regular
// n-gons to fill them with. Header-only.
#pragma once

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/test_support.h"

namespace tinbase::testing {

using PointList = std::vector<std::pair<double, double>>;

// A regular n-gon of radius r around (x, y), counter-clockwise, closed.
inline PointList Ngon(double x, double y, double r, int n, double phase = 0.1) {
  PointList ring;
  for (int k = 0; k <= n; ++k) {
    const double a = phase + 2 * M_PI * (k % n) / n;
    ring.push_back({x + r * std::cos(a), y + r * std::sin(a)});
  }
  return ring;
}

// One GeoJSON polygon feature per entry (shell, then holes), property "unit" = "u<index>", in
// `epsg`; coordinates written to 17 digits.
inline std::string WritePolygons(const TempDir& dir, const std::string& name,
                                 const std::vector<std::vector<PointList>>& polygons,
                                 int epsg = 28350) {
  const std::string path = dir.Path(name);
  std::ofstream out(path);
  out.precision(17);
  out << R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": )"
      << R"("urn:ogc:def:crs:EPSG::)" << epsg << R"("}}, "features": [)";
  for (size_t f = 0; f < polygons.size(); ++f) {
    out << (f ? "," : "") << R"({"type": "Feature", "properties": {"unit": "u)" << f
        << R"("}, "geometry": {"type": "Polygon", "coordinates": [)";
    for (size_t r = 0; r < polygons[f].size(); ++r) {
      out << (r ? "," : "") << "[";
      for (size_t i = 0; i < polygons[f][r].size(); ++i)
        out << (i ? "," : "") << "[" << polygons[f][r][i].first << "," << polygons[f][r][i].second
            << "]";
      out << "]";
    }
    out << "]}}";
  }
  out << "]}\n";
  return path;
}

}  // namespace tinbase::testing
