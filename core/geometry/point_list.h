// PointList: plan points read from text, one per line, for commands that query many points at
// once (`tinbase dem sample --points`).
//
// A line holds x and y separated by white space, a comma or a semicolon; further fields are
// ignored (a CSV of x,y,name works). Blank lines and lines starting with '#' are skipped, and so
// is a first line whose first two fields are not numbers (a CSV header). When that header names
// an x and a y column (`x` or `easting`, `y` or `northing`, any case), those columns are read
// instead, wherever they are, empty fields counting as columns. Anything else that is not two
// finite numbers is an error naming the source and the line. Thread-safety: pure.
#pragma once

#include <istream>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/predicates.h"

namespace tinbase {

// InvalidArgument "SOURCE:LINE: ..." for a bad line; `source` names the input in messages.
Result<std::vector<Point2>> ReadPointList(std::istream& in, const std::string& source);

}  // namespace tinbase
