// Reading a request's parameters, each checked once.
#include "service/request_params.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "db/query/surface_selection.h"

namespace tinbase::service {

namespace {

Status BadParam(const char* name, const std::string& text, const std::string& why) {
  return Status::InvalidArgument("parameter '" + std::string(name) + "': '" + text + "' " + why);
}

Result<double> ParseFinite(const char* name, const std::string& text) {
  if (text.empty()) return BadParam(name, text, "is empty");
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return BadParam(name, text, "is not a number");
  if (!std::isfinite(value) || errno == ERANGE)
    return BadParam(name, text, "is not a finite number");
  return value;
}

Result<int64_t> ParseInteger(const char* name, const std::string& text, int64_t min, int64_t max) {
  if (text.empty()) return BadParam(name, text, "is empty");
  errno = 0;
  char* end = nullptr;
  const long long value = std::strtoll(text.c_str(), &end, 10);
  if (end != text.c_str() + text.size()) return BadParam(name, text, "is not a whole number");
  if (errno == ERANGE || value < min || value > max)
    return BadParam(name, text,
                    "is out of range (" + std::to_string(min) + " to " + std::to_string(max) + ")");
  return static_cast<int64_t>(value);
}

}  // namespace

std::optional<std::string> OptionalParam(const httplib::Request& req, const char* name) {
  if (!req.has_param(name)) return std::nullopt;
  return req.get_param_value(name);
}

Result<std::string> RequiredParam(const httplib::Request& req, const char* name) {
  if (!req.has_param(name))
    return Status::InvalidArgument("missing parameter '" + std::string(name) + "'");
  return req.get_param_value(name);
}

Result<double> FiniteParam(const httplib::Request& req, const char* name) {
  TB_ASSIGN_OR_RETURN(std::string text, RequiredParam(req, name));
  return ParseFinite(name, text);
}

Result<int64_t> IntegerParam(const httplib::Request& req, const char* name, int64_t min,
                             int64_t max, std::optional<int64_t> fallback) {
  if (!req.has_param(name)) {
    if (fallback) return *fallback;
    return Status::InvalidArgument("missing parameter '" + std::string(name) + "'");
  }
  return ParseInteger(name, req.get_param_value(name), min, max);
}

Result<std::optional<Box>> BboxParam(const httplib::Request& req, const char* name) {
  if (!req.has_param(name)) return std::optional<Box>();
  auto box = ParseBbox(req.get_param_value(name));
  if (!box.ok()) return box.status().WithContext("parameter '" + std::string(name) + "'");
  return std::optional<Box>(*box);
}

Result<bool> BoolParam(const httplib::Request& req, const char* name, bool fallback) {
  if (!req.has_param(name)) return fallback;
  const std::string text = req.get_param_value(name);
  if (text == "true" || text == "1") return true;
  if (text == "false" || text == "0") return false;
  return BadParam(name, text, "is not true, false, 1 or 0");
}

Result<std::vector<Point2>> LineParam(const httplib::Request& req, const char* name) {
  TB_ASSIGN_OR_RETURN(std::string text, RequiredParam(req, name));
  std::vector<double> numbers;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    const std::string part = text.substr(start, comma - start);
    auto value = ParseFinite(name, part);
    if (!value.ok())
      return Status::InvalidArgument("parameter '" + std::string(name) + "', number " +
                                     std::to_string(numbers.size() + 1) + ": '" + part +
                                     "' is not a finite number");
    numbers.push_back(*value);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (numbers.size() % 2 != 0 || numbers.size() < 4)
    return BadParam(name, text,
                    "is not a line x1,y1,x2,y2,... of at least two points (got " +
                        std::to_string(numbers.size()) + " numbers)");
  std::vector<Point2> line;
  for (size_t i = 0; i < numbers.size(); i += 2) line.push_back({numbers[i], numbers[i + 1]});
  return line;
}

Result<std::optional<Crs>> CrsParam(const httplib::Request& req, const char* name) {
  if (!req.has_param(name)) return std::optional<Crs>();
  const std::string text = req.get_param_value(name);
  auto crs = Crs::FromUserInput(text);
  if (!crs.ok()) return BadParam(name, text, "is not a coordinate system GDAL knows");
  return std::optional<Crs>(std::move(*crs));
}

Result<SurfaceFilter> FilterParams(const httplib::Request& req) {
  SurfaceFilter filter;
  TB_ASSIGN_OR_RETURN(filter.bbox, BboxParam(req));
  TB_ASSIGN_OR_RETURN(filter.feature,
                      IntegerParam(req, "feature", 1, std::numeric_limits<int64_t>::max(), 0));
  TB_ASSIGN_OR_RETURN(filter.visible_only, BoolParam(req, "visible_only", false));
  if (auto tag = OptionalParam(req, "tag")) filter.tag = *tag;
  return filter;
}

Result<int64_t> IntegerPathPart(const httplib::Request& req, size_t index, const char* what,
                                int64_t min, int64_t max) {
  if (index >= req.matches.size())
    return Status::InvalidArgument("the path has no " + std::string(what));
  return ParseInteger(what, req.matches[index].str(), min, max);
}

Result<SurfaceInfo> SurfaceFromPath(Store& store, const httplib::Request& req, size_t index) {
  if (index >= req.matches.size()) return Status::InvalidArgument("the path names no surface");
  return SurfaceStore(store).Find(req.matches[index].str());
}

}  // namespace tinbase::service
