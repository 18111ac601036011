#include "core/pointcloud/xyz_reader.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <vector>

namespace tinbase {
namespace {

// A line with a comma is CSV (fields trimmed, so "1, 2,3" works and "1,,3" has an empty
// field); any other line is split at runs of whitespace.
std::vector<std::string> SplitFields(const std::string& line) {
  std::vector<std::string> fields;
  const bool csv = line.find(',') != std::string::npos;
  std::string field;
  const auto flush = [&](bool keep_empty) {
    const size_t b = field.find_first_not_of(" \t\r");
    const size_t e = field.find_last_not_of(" \t\r");
    field = b == std::string::npos ? "" : field.substr(b, e - b + 1);
    if (keep_empty || !field.empty()) fields.push_back(field);
    field.clear();
  };
  for (char c : line) {
    if (csv ? c == ',' : (c == ' ' || c == '\t' || c == '\r')) {
      flush(csv);
    } else {
      field += c;
    }
  }
  flush(false);
  return fields;
}

// The whole field as a double; nullopt when it is not one number.
std::optional<double> ParseNumber(const std::string& field) {
  double value = 0;
  const char* begin = field.data();
  const char* end = begin + field.size();
  if (begin != end && *begin == '+') ++begin;
  auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec == std::errc::result_out_of_range) return HUGE_VAL;  // reported as not finite
  if (ec != std::errc() || ptr != end || begin == end) return std::nullopt;
  return value;
}

}  // namespace

Result<PointCloud> ReadXyz(std::istream& in, const std::string& name) {
  PointCloud cloud;
  std::string line;
  bool seen_data = false;
  static const char* kAxis[] = {"x", "y", "z"};
  for (int64_t line_no = 1; std::getline(in, line); ++line_no) {
    const size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    const std::string where = name + ", line " + std::to_string(line_no);
    const std::vector<std::string> fields = SplitFields(line.substr(start));
    if (fields.size() < 3) {
      return Status::InvalidArgument(where + ": expected x y z, found " +
                                     std::to_string(fields.size()) + " field(s)");
    }
    std::optional<double> v[3];
    for (int i = 0; i < 3; ++i) v[i] = ParseNumber(fields[i]);
    if (!seen_data && !v[0] && !v[1] && !v[2]) {
      seen_data = true;  // a header line of names
      continue;
    }
    seen_data = true;
    CloudPoint p;
    double* out[3] = {&p.x, &p.y, &p.z};
    for (int i = 0; i < 3; ++i) {
      if (!v[i]) {
        return Status::InvalidArgument(where + ": " + kAxis[i] + " '" + fields[i] +
                                       "' is not a number");
      }
      if (!std::isfinite(*v[i])) {
        return Status::InvalidArgument(where + ": " + kAxis[i] + " '" + fields[i] +
                                       "' is not finite");
      }
      *out[i] = *v[i];
    }
    cloud.points.push_back(p);
  }
  if (in.bad()) return Status::IOError(name + ": read error");
  return cloud;
}

Result<PointCloud> ReadXyz(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Status::IOError(path + ": cannot open file");
  return ReadXyz(in, path);
}

}  // namespace tinbase
