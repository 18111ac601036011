#include "core/geometry/point_list.h"

#include <charconv>
#include <cmath>
#include <string_view>

namespace tinbase {
namespace {

bool IsSeparator(char c) { return c == ' ' || c == '\t' || c == ',' || c == ';' || c == '\r'; }

// The next field of `line` from `*at`, skipping separators before it; empty at the end.
std::string_view NextField(std::string_view line, size_t* at) {
  while (*at < line.size() && IsSeparator(line[*at])) ++*at;
  const size_t begin = *at;
  while (*at < line.size() && !IsSeparator(line[*at])) ++*at;
  return line.substr(begin, *at - begin);
}

bool ParseNumber(std::string_view field, double* value) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), *value);
  return ec == std::errc() && end == field.data() + field.size() && !field.empty();
}

}  // namespace

Result<std::vector<Point2>> ReadPointList(std::istream& in, const std::string& source) {
  std::vector<Point2> points;
  std::string line;
  bool first = true;
  for (int64_t number = 1; std::getline(in, line); ++number) {
    size_t at = 0;
    const std::string_view x_text = NextField(line, &at);
    if (x_text.empty() || x_text.front() == '#') continue;
    const std::string_view y_text = NextField(line, &at);
    const bool header = first;
    first = false;
    Point2 p;
    const bool x_ok = ParseNumber(x_text, &p.x), y_ok = ParseNumber(y_text, &p.y);
    if (header && !x_ok && !y_ok) continue;
    const std::string where = source + ":" + std::to_string(number) + ": ";
    if (y_text.empty())
      return Status::InvalidArgument(where + "expected 'x y' or 'x,y', got '" + line + "'");
    if (!x_ok || !y_ok)
      return Status::InvalidArgument(where + "'" + std::string(x_ok ? y_text : x_text) +
                                     "' is not a number");
    if (!std::isfinite(p.x) || !std::isfinite(p.y))
      return Status::InvalidArgument(where + "coordinates must be finite, got '" + line + "'");
    points.push_back(p);
  }
  if (in.bad()) return Status::IOError(source + ": read failed");
  return points;
}

}  // namespace tinbase
