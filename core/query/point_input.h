// Point input for queries over many points (bulk location, profile lines): plain x,y text, CSV
// with a header, or any point layer OGR reads (GeoJSON, GeoPackage, shapefile, ...).
//
// The whole input is read and checked before anything is returned, so a caller that streams
// answers prints none for an input with a bad line: it gets every point or one error naming the
// file and the 1-based line (text) or the feature (OGR). Thread-safety: reentrant (standard
// input is read by one caller at a time).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/geometry/predicates.h"

namespace tinbase {

// The points of `path`: standard input for "-", the first layer of any vector source OGR opens
// other than its CSV driver (every feature a Point, reprojected to `target_crs` when it is given
// and the layer declares another CRS), and x,y text for everything else: one point a line, a
// header naming the x and y columns if any (ReadPointList, core/geometry/point_list.h). Errors:
// NotFound when the file does not exist; InvalidArgument "file:7: ..." naming the line of bad
// text (ReadPointList's), "file: no points" when there are none; for a vector source,
// InvalidArgument naming the file and feature for a feature that is not a point, and the file
// for a source of more than one layer or coordinates that cannot be reprojected.
Result<std::vector<Point2>> ReadPoints(const std::string& path,
                                       const std::optional<Crs>& target_crs = std::nullopt);

// The vertices of a polyline, in order: x,y text or an OGR point layer as ReadPoints reads them,
// or an OGR layer holding one LineString feature. Errors as ReadPoints', and InvalidArgument
// naming the file for a line layer of more than one feature.
Result<std::vector<Point2>> ReadLine(const std::string& path,
                                     const std::optional<Crs>& target_crs = std::nullopt);

// Points typed on the command line: "x,y" pairs separated by spaces or ';' ("0,0 10,5;20,0").
// InvalidArgument "`what` 'text': point k 'token' is not x,y" (k 1-based) otherwise, or for no
// points at all.
Result<std::vector<Point2>> ParsePointList(const std::string& text, const std::string& what);

}  // namespace tinbase
