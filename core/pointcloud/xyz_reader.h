// XyzReader: reads plain-text point files, one "x y z" per line.
//
// Fields are separated by commas when the line has one (CSV; spaces around them are trimmed),
// else by whitespace. Blank lines and lines starting with '#'
// are skipped; the first data line may be a header of names ("x,y,z"), recognised because its
// first three fields are not numbers. Fields after the third are ignored. The file has no CRS
// and no classes (every point gets class 0). Stateless; thread-safe.
#pragma once

#include <istream>
#include <string>

#include "core/base/status.h"
#include "core/pointcloud/point_cloud.h"

namespace tinbase {

// Reads every point of the file at `path`. Errors name the file and the 1-based line:
// IOError when it cannot be opened; InvalidArgument when a line has fewer than three fields,
// a field that is not a number, or a number that is not finite.
Result<PointCloud> ReadXyz(const std::string& path);

// As ReadXyz, from a stream; `name` stands for the file in messages.
Result<PointCloud> ReadXyz(std::istream& in, const std::string& name);

}  // namespace tinbase
