#include "core/geometry/point_list.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <string_view>

#include "core/base/number_text.h"

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

std::string_view Trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// Every field of a line, empty ones kept: split at commas when it has one, else at semicolons,
// else at white space (where runs of it are one separator).
std::vector<std::string_view> AllFields(std::string_view line) {
  std::vector<std::string_view> fields;
  const char split = line.find(',') != std::string_view::npos   ? ','
                     : line.find(';') != std::string_view::npos ? ';'
                                                                : ' ';
  if (split == ' ') {
    size_t at = 0;
    for (std::string_view f = NextField(line, &at); !f.empty(); f = NextField(line, &at))
      fields.push_back(f);
    return fields;
  }
  size_t start = 0;
  for (;;) {
    const size_t end = line.find(split, start);
    fields.push_back(Trim(line.substr(start, end - start)));
    if (end == std::string_view::npos) return fields;
    start = end + 1;
  }
}

// False when `field` is no number at all; a number that is not usable is checked per point.
bool ParseNumber(std::string_view field, double* value) {
  const NumberText n = ParseNumberText(field);
  *value = n.value;
  return n.problem != NumberProblem::kNotANumber;
}

// The header's column named one of `names` (any case, quotes ignored), or -1.
int ColumnNamed(const std::vector<std::string_view>& header,
                std::initializer_list<std::string_view> names) {
  for (size_t i = 0; i < header.size(); ++i) {
    std::string_view f = header[i];
    if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = f.substr(1, f.size() - 2);
    for (std::string_view name : names)
      if (std::equal(f.begin(), f.end(), name.begin(), name.end(), [](char a, char b) {
            return std::tolower(static_cast<unsigned char>(a)) == b;
          }))
        return static_cast<int>(i);
  }
  return -1;
}

// The x and y columns a header names, when it names both.
struct NamedColumns {
  int x = 0;
  int y = 1;
};
std::optional<NamedColumns> HeaderColumns(std::string_view line) {
  const std::vector<std::string_view> header = AllFields(line);
  const NamedColumns c{ColumnNamed(header, {"x", "easting"}),
                       ColumnNamed(header, {"y", "northing"})};
  if (c.x < 0 || c.y < 0) return std::nullopt;
  return c;
}

// x and y from the columns a header named.
Status ReadNamed(std::string_view line, const NamedColumns& c, const std::string& where,
                 Point2* p) {
  const std::vector<std::string_view> fields = AllFields(line);
  const size_t needed = static_cast<size_t>(std::max(c.x, c.y)) + 1;
  if (fields.size() < needed)
    return Status::InvalidArgument(where + std::to_string(fields.size()) +
                                   " field(s), the header's x and y need " +
                                   std::to_string(needed));
  for (const auto& [column, value] : {std::pair{c.x, &p->x}, std::pair{c.y, &p->y}}) {
    const std::string_view field = fields[static_cast<size_t>(column)];
    if (!ParseNumber(field, value))
      return Status::InvalidArgument(where + "'" + std::string(field) + "' is not a number");
  }
  return Status::Ok();
}

}  // namespace

Result<std::vector<Point2>> ReadPointList(std::istream& in, const std::string& source) {
  std::vector<Point2> points;
  std::string line;
  bool first = true;
  std::optional<NamedColumns> named;
  for (int64_t number = 1; std::getline(in, line); ++number) {
    size_t at = 0;
    const std::string_view x_text = NextField(line, &at);
    if (x_text.empty() || x_text.front() == '#') continue;
    const std::string_view y_text = NextField(line, &at);
    const bool header = first;
    first = false;
    const std::string where = source + ":" + std::to_string(number) + ": ";
    Point2 p;
    if (named) {
      TB_RETURN_IF_ERROR(ReadNamed(line, *named, where, &p));
    } else {
      const bool x_ok = ParseNumber(x_text, &p.x), y_ok = ParseNumber(y_text, &p.y);
      if (header && !x_ok && !y_ok) {
        named = HeaderColumns(line);
        continue;
      }
      if (y_text.empty())
        return Status::InvalidArgument(where + "expected 'x y' or 'x,y', got '" + line + "'");
      if (!x_ok || !y_ok)
        return Status::InvalidArgument(where + "'" + std::string(x_ok ? y_text : x_text) +
                                       "' is not a number");
    }
    if (CheckNumber(p.x) || CheckNumber(p.y))
      return Status::InvalidArgument(where + "coordinates must be finite and at most 1e15 in " +
                                     "magnitude, got '" + line + "'");
    points.push_back(p);
  }
  if (in.bad()) return Status::IOError(source + ": read failed");
  return points;
}

}  // namespace tinbase
