// SurveyPoints: the points a `points add` file holds (spot heights, GNSS shots), each with its
// own z and a label that names it in messages, in the store's CRS.
//
// Formats: LAS (.las; every point, whatever its class) and XYZ/CSV text through the point cloud
// readers (core/pointcloud/point_tin.h ReadPointFile), and any OGR vector source with Point Z or
// MultiPoint Z features (.geojson, .json, .gpkg, .shp, .fgb, .gml, .kml). Points are in file
// order, none left out. Thread-safety: stateless; GDAL errors are caught per thread.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/tin/tin.h"

namespace tinbase {

struct SurveyPoints {
  std::vector<TinVertex> points;    // kind kUser, file order, in the target CRS
  std::vector<std::string> labels;  // per point: "shots.csv, point 3", "a.geojson, feature 2"
  std::string format;               // "XYZ", "LAS 1.2, point format 3", "GeoJSON"
  std::string reprojected_from;     // the file's CRS label when it was reprojected, else empty
};

// The points of `path`, reprojected to `target` when the file names another CRS (x and y; z
// follows the unit, as `points import` does). InvalidArgument naming the file and the feature or
// line: a feature that is not a Point or MultiPoint, a point without z, a non-finite coordinate,
// no point at all, a vector source of several layers; IOError when it cannot be opened.
Result<SurveyPoints> ReadSurveyPoints(const std::string& path, const std::optional<Crs>& target);

}  // namespace tinbase
