// Point input for queries over many points (bulk location, profile lines): plain x,y text, CSV
// with a header, or any point layer OGR reads (GeoJSON, GeoPackage, shapefile, ...).
//
// The whole input is read and checked before anything is returned, so a caller that streams
// answers prints none for an input with a bad line: it gets every point or one error naming the
// file and the 1-based line (text) or the feature (OGR). Thread-safety: reentrant.
#pragma once

#include <cstdint>
#include <istream>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/geometry/predicates.h"

namespace tinbase {

// Reads x,y text from `in`; `name` stands for the file in messages. One point a line, its
// fields separated by a comma when the line has one, else by whitespace; blank lines and lines
// starting with '#' are skipped. A first data line whose first field is not a number is a
// header: the columns named x and y (or easting and northing, any case) are then read, and
// other columns ignored; without a header x and y are the first two fields and more are
// ignored. InvalidArgument "name, line 7: ..." for a line with too few fields, a field that is
// not a number or a number that is not finite, and for a header without x and y columns;
// InvalidArgument "name: no points" when there are none.
Result<std::vector<Point2>> ReadPointText(std::istream& in, const std::string& name);

// The points of `path`: standard input for "-", the first layer of any vector source OGR opens
// other than its CSV driver (every feature a Point, reprojected to `target_crs` when it is given
// and the layer declares another CRS), and x,y text (ReadPointText) for everything else. Errors:
// NotFound when the file does not exist; ReadPointText's; for a vector source, InvalidArgument
// naming the file and feature for a feature that is not a point, and the file for a source of
// more than one layer, no features, or coordinates that cannot be reprojected.
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
