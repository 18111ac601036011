// Crs: a coordinate reference system, as GDAL/PROJ understand it.
//
// Wraps OGRSpatialReference so the rest of tinbase deals in values: parse what a user typed
// ("EPSG:32632", WKT, PROJ strings), compare two systems, tell geographic from projected, and
// pick the UTM zone for geographic data (GeographicLib's standard zone rule, which knows the
// Norway and Svalbard exceptions). Axis order is always x = easting/longitude, y =
// northing/latitude. Thread-safety: immutable after construction.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "core/base/status.h"

class OGRSpatialReference;

namespace tinbase {

class Crs {
 public:
  // Parses "EPSG:n", WKT or anything OGRSpatialReference::SetFromUserInput takes.
  static Result<Crs> FromUserInput(const std::string& text);
  // Parses WKT from a store or a raster; InvalidArgument when it is empty or unreadable.
  static Result<Crs> FromWkt(const std::string& wkt);
  // The WGS 84 UTM zone (EPSG:326zz north, 327zz south) that holds (lon, lat).
  static Result<Crs> UtmFor(double lon, double lat);

  Crs(const Crs& other);
  Crs& operator=(const Crs& other);
  Crs(Crs&&) noexcept;
  Crs& operator=(Crs&&) noexcept;
  ~Crs();

  std::string Wkt() const;
  // The EPSG code when the system is identified as one, else nullopt.
  std::optional<int> Epsg() const;
  // "EPSG:32632" when known, else the system's name.
  std::string Label() const;
  bool IsGeographic() const;
  // Metres per unit of height: the vertical CRS's unit for a compound system, else (LAS and
  // most height data without a vertical CRS give z in the horizontal unit) the projected linear
  // unit; 1 for a geographic system.
  double VerticalMetresPerUnit() const;
  // True when both describe the same system (ignoring axis-order and naming differences).
  bool IsSame(const Crs& other) const;

  const OGRSpatialReference& ogr() const { return *srs_; }

 private:
  explicit Crs(std::unique_ptr<OGRSpatialReference> srs);
  std::unique_ptr<OGRSpatialReference> srs_;
};

}  // namespace tinbase
